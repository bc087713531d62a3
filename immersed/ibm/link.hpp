// The immersed boundary's messages between immersed and fluid (both sides):
// the markers go out from immersed rank 0 to every fluid rank at the start of
// a window (an empty message when nothing moved), and the loads on the bodies
// come back from fluid rank 0 at its end. Nothing goes per iteration of the
// multi-direct forcing: the fluid iterates alone.
#pragma once

#include <mpi.h>

#include <vector>

namespace coflow::ibm {

// Immersed side (collective over the immersed ranks, who all know `due`):
// rank 0's `packed` goes when due, else an empty message.
void send_markers(MPI_Comm fluid, int rank, bool due, const std::vector<double>& packed);
// Fluid side (collective over the fluid ranks): false when no markers came.
bool receive_markers(MPI_Comm immersed, std::vector<double>& packed);
// Fluid rank 0 sends, immersed rank 0 receives `values` (its size known).
void send_loads(MPI_Comm immersed, const std::vector<double>& values);
void receive_loads(MPI_Comm fluid, std::vector<double>& values);

}  // namespace coflow::ibm
