#!/usr/bin/env bash
# run.sh SOURCE_DIR BUILD_DIR WORK_DIR
# Install coflow into a prefix, build tests/install against it with
# find_package(coflow), and run the result as an external fluid component.
set -eu
src=$1 build=$2 work=$3
rm -rf "$work"; mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"
cmake -S "$src/tests/install" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" >"$work/configure.log" 2>&1 ||
  { tail -n 20 "$work/configure.log"; exit 1; }
cmake --build "$work/build" -j2 >"$work/build.log" 2>&1 || { grep -E "error" "$work/build.log" | head; exit 1; }
cat >"$work/case.yaml" <<YAML
run: {name: my-fluid, end_time: 1.0, output: {dir: $work/out}}
domain: {lower: [0, 0, 0], upper: [1, 1, 1], cells: [4, 4, 4]}
fluid: {solver: external, ranks: 2, any_key_of_mine: 42}
YAML
"$work/prefix/bin/coflow" run "$work/case.yaml" --exe fluid="$work/build/my-fluid" >"$work/run.log" 2>&1 ||
  { cat "$work/run.log"; exit 1; }
grep -q '"my_fluid.window_sum": 10' "$work/out/summary.json" || { cat "$work/out/summary.json"; exit 1; }
echo "installed coflow, built an out-of-tree component with find_package(coflow), ran it: ok"
