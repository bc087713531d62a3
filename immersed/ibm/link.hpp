// The immersed boundary's messages between immersed and fluid (both sides):
// the markers go out from immersed rank 0 to every fluid rank at the start of
// a window, and the loads on the bodies
// come back from fluid rank 0 at its end. Nothing goes per iteration of the
// multi-direct forcing: the fluid iterates alone. When no body moves, the
// first broadcast says that its markers hold for the rest of the run, and no
// broadcast follows: the fluid then does not wait for immersed (its loads are
// small sends, which normally complete without the receiver).
#pragma once

#include <mpi.h>

#include <vector>

namespace coflow::ibm {

// Immersed side (collective over the immersed ranks, who all know `last`):
// rank 0's `packed` goes (the payload's count matters at the root only);
// `last`: these markers hold to the end of the run, none follow.
void send_markers(MPI_Comm fluid, int rank, bool last, const std::vector<double>& packed);
// Fluid side (collective over the fluid ranks): false when no markers came;
// `last` set when they hold to the end (receive no more).
bool receive_markers(MPI_Comm immersed, std::vector<double>& packed, bool& last);
// Fluid rank 0 sends, immersed rank 0 receives `values` (its size known).
void send_loads(MPI_Comm immersed, const std::vector<double>& values);
void receive_loads(MPI_Comm fluid, std::vector<double>& values);

}  // namespace coflow::ibm
