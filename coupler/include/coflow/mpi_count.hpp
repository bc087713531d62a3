// MPI counts are int: a message (or the sum of a gather) past 2^31 - 1
// elements would wrap.
#pragma once

#include <cstddef>
#include <string_view>

namespace coflow::coupler {

// An MPI count (int) for n elements of one message: past 2^31 - 1 it would
// wrap, so it throws instead, naming the message (`what` and the field's
// `name`, if any) and telling the user to spread the components over more ranks.
int mpi_count(std::size_t n, std::string_view what, std::string_view name = {});

}  // namespace coflow::coupler
