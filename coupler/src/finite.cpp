#include "coflow/finite.hpp"

#include <cmath>
#include <cstddef>

#include <fmt/format.h>

#include "coflow/session.hpp"

namespace coflow::coupler {

void check_finite(MPI_Comm comm, const FiniteCheck& what, long step, double time, const std::vector<FiniteField>& fields,
                  int per_item, std::span<const std::int64_t> ids) {
  const FiniteField* field = nullptr;
  std::size_t bad = 0;
  for (const FiniteField& f : fields) {
    for (std::size_t i = 0; i < f.values.size() && !field; ++i)
      if (!std::isfinite(f.values[i])) {
        field = &f;
        bad = i;
      }
    if (field) break;
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  int mine = field ? rank : size, first = size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm);
  if (first == size) return;
  std::string where = fmt::format("on rank {}", first), name = "state";
  if (first == rank) {
    const std::size_t item = bad / static_cast<std::size_t>(per_item);
    const std::string who = item < ids.size() ? fmt::format("{} {}", what.item, ids[item])
                                              : fmt::format("{} {} of rank {}", what.item, item, rank);
    where = fmt::format("{} (component {} is {})", who, bad % static_cast<std::size_t>(per_item), field->values[bad]);
    name = field->name;
  }
  throw SolverError(fmt::format("{}: {} is not finite at step {} (t = {:.6g} s), {}{}{}", what.component, name, step,
                                time, where, what.hint.empty() ? "" : "; ", what.hint));
}

}  // namespace coflow::coupler
