// The point method has no keys of its own yet.
#pragma once

#include "coflow/config.hpp"

namespace coflow::immersed {

struct PointParams {
  void visit(config::Visitor&) {}  // trilinear interpolation and spreading: nothing to choose yet
};

}  // namespace coflow::immersed
