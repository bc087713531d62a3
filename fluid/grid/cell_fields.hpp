// Cell fields on the fluid grid, for any fluid method (lbm now, fv next): the
// owned block of each rank is one part of a global field. A checkpoint of cell
// fields is one HDF5 file of global datasets, so a run may restart on another
// rank count.
#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "coflow/decomposition.hpp"
#include "coflow/output.hpp"

namespace coflow::fluid::grid {

// Collective over `comm`: each field (owned cells, x fastest, `components` per
// cell) into one global dataset [nz][ny][nx][c] of `path`, with the time and step.
void save_cell_fields(MPI_Comm comm, const std::string& path, double time, long step, const coupler::Index3& cells,
                      const coupler::Box& owned, const std::vector<output::GridField>& fields);

// The owned block (x fastest, `components` per cell) of field `name` of a file
// written by save_cell_fields with any rank count. Throws, naming the file,
// when its grid or its components differ from `cells` and `components`, and
// naming the cell, when one of the owned values is not finite (a damaged
// checkpoint: a run would stop later with a message that blames its step).
std::vector<double> load_cell_field(const std::string& path, const std::string& name, const coupler::Index3& cells,
                                    const coupler::Box& owned, int components);

// A small file of the checkpoint, the same on every rank: rank 0 writes
// `text` into `path` (atomically); collective, and throws (output::WriteError,
// naming the file) on every rank when it could not.
void save_text(MPI_Comm comm, const std::string& path, const std::string& text);
// A number of the checkpoint beside its cell fields, the same on every rank:
// rank 0 writes `value` exactly (a hexadecimal float) into `path`. Collective;
// throws on every rank when it cannot be written.
void save_number(MPI_Comm comm, const std::string& path, double value);
// The number save_number wrote into `path`, or `absent` where there is no such
// file (a checkpoint written before the number was). Throws, naming the file,
// when it holds no finite number of zero or more (the numbers saved so far).
double load_number(const std::string& path, double absent);

}  // namespace coflow::fluid::grid
