#include "coflow/finite.hpp"

#include <cmath>
#include <cstddef>

#include <fmt/format.h>

#include "coflow/session.hpp"

namespace coflow::coupler {

void check_finite(MPI_Comm comm, const FiniteCheck& what, long step, double time, std::span<const double> values,
                  int per_item, std::span<const std::int64_t> ids) {
  std::size_t bad = values.size();
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i])) {
      bad = i;
      break;
    }
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int mine = bad < values.size() ? rank : size, first = size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  std::string where = fmt::format("on rank {}", first);
  if (first == rank) {
    const std::size_t item = bad / static_cast<std::size_t>(per_item);
    const std::string name = item < ids.size() ? fmt::format("{} {}", what.item, ids[item])
                                               : fmt::format("{} {} of rank {}", what.item, item, rank);
    where = fmt::format("{} (component {} is {})", name, bad % static_cast<std::size_t>(per_item), values[bad]);
  }
  throw SolverError(fmt::format("{}: {} is not finite at step {} (t = {:.6g} s), {}{}{}", what.component, what.field,
                                step, time, where, what.hint.empty() ? "" : "; ", what.hint));
}

}  // namespace coflow::coupler
