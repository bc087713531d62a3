// Sums over the ranks whose bits do not depend on the order of the terms or
// on how they are split among the ranks: 1 rank gives the same sums as N.
// Each term is pre-rounded to a grid set by the largest term on any rank and
// by the number of terms, fine enough that every partial sum on that grid is
// exact (Demmel & Nguyen 2015, "Parallel reproducible summation", IEEE Trans.
// Comput. 64(7), 2060-2070, §III). Three such levels, each taking the
// remainder of the one before, are summed exactly and added in a fixed order
// at the end. The error is at most n 2^(e + 3b - 159) (n terms, b =
// bit_width(n) + 1, all terms below 2^e): about 1e-23 of the largest term for
// a million terms, below a double's own rounding of the sum.
#pragma once

#include <mpi.h>

#include <span>
#include <vector>

namespace coflow::coupler {

// `terms` holds n rows of `width` terms (row-major); returns the `width`
// column sums, the same on every rank (collective: three reductions). A
// column with a NaN, an infinity or a term beyond 2^960 anywhere gives the
// plain sum.
std::vector<double> reproducible_sums(MPI_Comm comm, std::span<const double> terms, int width);

}  // namespace coflow::coupler
