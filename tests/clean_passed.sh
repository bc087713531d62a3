#!/usr/bin/env bash
# clean_passed.sh DIR...: removes the HDF5 files a passing test wrote under
# each DIR (its snapshots and the HDF5 part of its checkpoints), with the
# *.xdmf files that index them; its logs, series, event logs, summaries and
# metrics stay. Over the whole suite the snapshots came to 2.4 GB, which
# filled a CI machine's disk half-way through on 2026-12-06; with this the
# suite leaves about 0.3 GB. Called by a test script that passed (validate.sh,
# and an EXIT trap in the restart, interrupt and output scripts): a script
# that fails keeps everything. A ctest that chains two scripts
# (restart.fv_k_epsilon_log_law) keeps only the failing one's.
# COFLOW_KEEP_TEST_OUTPUT set to anything but 0 keeps everything.
[ "${COFLOW_KEEP_TEST_OUTPUT:-0}" = 0 ] || exit 0
for d in "$@"; do
  [ -d "$d" ] && find "$d" -type f \( -name '*.h5' -o -name '*.xdmf' \) -delete
done
exit 0
