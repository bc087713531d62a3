#include <stdexcept>

#include "coflow/catalog.hpp"
#include "coflow/session.hpp"

int main(int argc, char** argv) {
  return coflow::coupler::run_component("immersed", argc, argv, coflow::catalog(), [](coflow::coupler::Session& s) {
    const auto& info = s.config().component("immersed");
    throw std::runtime_error("immersed.method '" + info.variant +
                             "' has no built-in implementation; run your own executable with "
                             "`coflow run --exe immersed=PATH`");
  });
}
