// The check every component runs on the state it hands on: a NaN or an infinity
// stops the run at once, naming the component, the step, the field and the
// item, instead of surfacing later in another component (seed 000 eq. 2.38's
// Mach check is lbm's own version of this).
#pragma once

#include <mpi.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace coflow::coupler {

// One field to check: its name and values, per_item values an item.
struct FiniteField {
  std::string name;  // e.g. "velocity"
  std::span<const double> values;
};

// What a failed check names.
struct FiniteCheck {
  std::string component;  // e.g. "particles (dem)"
  std::string item;       // e.g. "particle" (the n-th item's id, if ids are given, is named)
  std::string hint;       // the likely cause and what to do
};

// Collective over comm (one reduction for all the fields): throws SolverError
// on every rank when any rank holds a non-finite value in any field. `ids`,
// when not empty, names the items (one id an item); otherwise their index on
// the rank.
void check_finite(MPI_Comm comm, const FiniteCheck& what, long step, double time, const std::vector<FiniteField>& fields,
                  int per_item, std::span<const std::int64_t> ids = {});

}  // namespace coflow::coupler
