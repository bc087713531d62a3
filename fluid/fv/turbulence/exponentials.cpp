// The exponentials of the two-layer closure's rows (fv::Closure::nu_t_row,
// near_wall_row), taken by glibc's vector exp (libmvec).
//
// This file alone is built with -ffast-math: glibc's <math.h> declares its
// vector exp (_ZGVeN8v_exp and the like) only then, and GCC calls it for the
// loop below, 8 (AVX-512) or 4 (AVX2) values a call; the last few values of
// a row take the scalar exp. The loop does nothing but the calls, so the
// flag changes no other arithmetic. libmvec's functions pass a 4-ulp
// criterion (glibc's wiki page "libmvec"); a value may differ from std::exp's
// in its last bits, and the per-cell closure (fv-reference) keeps std::exp.
#include "fluid/fv/turbulence/exponentials.hpp"

#include <cmath>

namespace coflow::fluid::fv {

void exp_in_place(double* a, long n) {
  for (long i = 0; i < n; ++i) a[i] = std::exp(a[i]);  // std::exp(double) is glibc's exp: no inline wrapper
}

}  // namespace coflow::fluid::fv
