#pragma once

#include "coflow/session.hpp"

namespace coflow::fluid {

// The fluid component's window loop.
void run(coupler::Session& session);

}  // namespace coflow::fluid
