// The immersed methods by name; their schemas are in immersed/schema.cpp.
#include "immersed/ibm/ibm.hpp"
#include "immersed/point/point.hpp"
#include "immersed/psm/psm.hpp"
#include "immersed/schema.hpp"

namespace coflow::immersed {

void register_immersed_variants(Registry<ImmersedMethod>& r) {
  r.add<PsmMethod>("psm");
  r.add<PointMethod>("point");
  r.add<IbmMethod>("ibm");
}

Registry<ImmersedMethod>& registry() {
  static Registry<ImmersedMethod> r = [] {
    Registry<ImmersedMethod> reg;
    register_immersed_variants(reg);
    return reg;
  }();
  return r;
}

}  // namespace coflow::immersed
