// Regularised delta functions of the immersed boundary (seed 003 eqs. 4.9 and
// 4.10: D_h = phi(r_x) phi(r_y) phi(r_z) / (dx dy dz), r in cells). The seed
// names its kernel only as the "hat function" (Vedovoto, Serfaty & Silveira
// Neto 2015) and gives no formula; `hat` here is the linear hat (tent)
// phi(r) = 1 - |r|, the two-point kernel. Roma, Peskin & Berger (1999) give
// the three-point kernel, Peskin (2002) the four-point one. Each sums to one
// over any row of grid points (sum_i phi(r - i) = 1), so spreading conserves
// the force and interpolating keeps a uniform field.
#pragma once

#include <cmath>
#include <string>
#include <vector>

namespace coflow::ibm {

enum class Kernel { hat, roma3, peskin4 };

inline const std::vector<std::string>& kernel_names() {
  static const std::vector<std::string> n{"hat", "roma3", "peskin4"};
  return n;
}

inline Kernel kernel_from_name(const std::string& name) {
  if (name == "roma3") return Kernel::roma3;
  if (name == "peskin4") return Kernel::peskin4;
  return Kernel::hat;
}

// The support's half-width in cells: phi(r) = 0 for |r| >= radius.
inline double kernel_radius(Kernel k) {
  switch (k) {
    case Kernel::hat: return 1.0;
    case Kernel::roma3: return 1.5;
    case Kernel::peskin4: return 2.0;
  }
  return 2.0;
}

inline double kernel(Kernel k, double r) {
  r = std::abs(r);
  switch (k) {
    case Kernel::hat:
      return r < 1.0 ? 1.0 - r : 0.0;
    case Kernel::roma3:  // Roma, Peskin & Berger (1999)
      if (r <= 0.5) return (1.0 + std::sqrt(1.0 - 3.0 * r * r)) / 3.0;
      if (r < 1.5) return (5.0 - 3.0 * r - std::sqrt(1.0 - 3.0 * (1.0 - r) * (1.0 - r))) / 6.0;
      return 0.0;
    case Kernel::peskin4:  // Peskin (2002), the four-point function
      if (r <= 1.0) return (3.0 - 2.0 * r + std::sqrt(1.0 + 4.0 * r - 4.0 * r * r)) / 8.0;
      if (r < 2.0) return (5.0 - 2.0 * r - std::sqrt(-7.0 + 12.0 * r - 4.0 * r * r)) / 8.0;
      return 0.0;
  }
  return 0.0;
}

}  // namespace coflow::ibm
