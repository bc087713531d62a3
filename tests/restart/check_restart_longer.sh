#!/usr/bin/env bash
# check_restart_longer.sh BIN_DIR CONFIG OUT END EVERY LONGER_END [--set ...]
# A run to END (not a multiple of run.output.every = EVERY) ends with a
# snapshot numbered as the next multiple. Restarted from its last checkpoint
# (at END) into its own directory with the longer end time LONGER_END, it must
# leave the directory as a run straight to LONGER_END does: the same snapshot
# indexes (numbers, times, fields) and the same run.xdmf, each snapshot number
# written once, and the final state bit for bit.
set -u
bin=$1 cfg=$2 out=$3 end=$4 every=$5 longer=$6; shift 6
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$out"; mkdir -p "$out"
run() { local dir=$1; shift; "$bin/coflow" run "$cfg" --set run.output.dir="$dir" --set run.output.every="$every" "$@" >"$dir.log" 2>&1 || { tail -n 20 "$dir.log"; fail "$dir"; }; }
run "$out/straight" --set run.end_time="$longer" "$@"
run "$out/extended" --set run.end_time="$end" --set run.checkpoint.every="$end" "$@"
short=$(cat "$out"/extended/*/index.csv)
run "$out/extended" --set run.end_time="$longer" --restart latest "$@"
grep -q "the run's last, which fell between two multiples of run.output.every" "$out/extended.log" ||
  { cat "$out/extended.log"; fail "the restart did not say that it removed the run's last snapshot"; }
for f in "$out"/straight/*/index.csv run.xdmf; do
  rel=${f#"$out/straight/"}
  [ "$f" = run.xdmf ] && rel=run.xdmf && f=$out/straight/run.xdmf
  cmp -s "$f" "$out/extended/$rel" ||
    { echo "before the restart:"; echo "$short"; diff "$f" "$out/extended/$rel" | head -20; fail "$rel differs from the straight run's"; }
done
dup=$(cut -d, -f1 "$out"/extended/fluid/index.csv | sort | uniq -d)
[ -z "$dup" ] || fail "snapshot number(s) $dup indexed twice"
m=$("$bin/coflow-check" compare "$out/straight" "$out/extended") || { echo "$m"; fail "compare"; }
nonzero=$(echo "$m" | grep -E '^[a-z_]+_difference=' | grep -vE '=0\.000000e\+00$')
[ -z "$nonzero" ] || fail "the extended run differs from the straight one: $nonzero"
echo "restart at t = $end with end time $longer: indexes and run.xdmf as the straight run's ($(wc -l <"$out/straight/fluid/index.csv") index lines), final state identical"
