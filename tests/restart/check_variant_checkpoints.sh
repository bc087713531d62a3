#!/usr/bin/env bash
# check_variant_checkpoints.sh BIN_DIR CONFIG OUT COMPONENT VARIANT_A VARIANT_B EVERY [--set ...]
# Two variants of one component that share a checkpoint format (dem and
# dem-reference) write the same checkpoint, to the bit: CONFIG runs with each,
# a checkpoint every EVERY seconds, and every file of COMPONENT's part of the
# last checkpoint is compared (HDF5: the same datasets and shapes, then h5diff,
# which must find nothing and no object it cannot compare but empty ones;
# other files byte by byte).
set -u
bin=$1 cfg=$2 out=$3 comp=$4 a=$5 b=$6 every=$7; shift 7
trap '[ $? -ne 0 ] || "$(dirname "$0")/../clean_passed.sh" "$out"' EXIT  # a failure keeps its snapshots
rm -rf "$out"; mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
for v in "$a" "$b"; do
  "$bin/coflow" run "$cfg" --set run.output.dir="$out/$v" --set "$comp.solver=$v" \
    --set run.checkpoint.every="$every" "$@" >"$out/$v.log" 2>&1 || { tail -n 20 "$out/$v.log"; fail "$v run"; }
done
last() { ls -d "$out/$1"/checkpoints/window_* | tail -n 1; }
da=$(last "$a")/$comp db=$(last "$b")/$comp
[ "$(basename "$(dirname "$da")")" = "$(basename "$(dirname "$db")")" ] || fail "the last checkpoints differ in window"
[ "$(ls "$da")" = "$(ls "$db")" ] || { ls "$da" "$db"; fail "the two checkpoints hold other files"; }
n=0
for f in "$da"/*; do
  g=$db/$(basename "$f")
  [ -f "$g" ] || fail "$(basename "$f") is missing from $b's checkpoint"
  case "$f" in
    *.h5) # the same datasets and shapes; then the values (h5diff cannot compare
          # empty datasets, which the shapes above already matched)
          [ "$(h5ls -r "$f" | sort)" = "$(h5ls -r "$g" | sort)" ] || { h5ls -r "$f"; h5ls -r "$g"; fail "$(basename "$f"): other datasets or shapes"; }
          h5diff "$f" "$g" >"$out/h5diff.txt" 2>&1; rc=$?
          d=$(grep -v -e 'is an empty dataset$' -e '^-*$' -e 'Some objects are not comparable' -e 'Use -c for a list' "$out/h5diff.txt")
          [ $rc -eq 0 ] && [ -z "$d" ] || { echo "$d" | head -n 10; fail "$(basename "$f") differs"; } ;;
    *) cmp -s "$f" "$g" || fail "$(basename "$f") differs" ;;
  esac
  n=$((n + 1))
done
[ "$n" -gt 0 ] || fail "no files in $da"
echo "ok: $n files of $comp's checkpoint identical in $a and $b ($(basename "$(dirname "$da")"))"
