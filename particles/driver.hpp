#pragma once

#include "coflow/session.hpp"

namespace coflow::particles {

// The particle component's window loop.
void run(coupler::Session& session);

}  // namespace coflow::particles
