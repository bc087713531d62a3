#!/usr/bin/env bash
# config_one_rank.sh BIN_DIR CONFIG OUT
# One rank cannot read the configuration (as on a node whose file system
# lacks it): the whole run must stop at once with that rank's message and
# exit status 2, not leave the other ranks waiting for it.
set -u
bin=$1 cfg=$2 out=$3
rm -rf "$out" "$out.log"; mkdir -p "$(dirname "$out")"
wrapper="$out.particles.sh"
# The particles' second rank (world rank 2: fluid and immersed have one each)
# is given a file that is not there in place of the resolved configuration.
cat >"$wrapper" <<WRAP
#!/bin/sh
if [ "\${OMPI_COMM_WORLD_RANK:-}" = 2 ]; then shift; set -- "$out.missing.yaml" "\$@"; fi
exec "$bin/coflow-dummy-particles" "\$@"
WRAP
chmod +x "$wrapper"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
start=$(date +%s%N)
timeout 60 "$bin/coflow" run "$cfg" --exe fluid="$bin/coflow-dummy-fluid" --exe immersed="$bin/coflow-dummy-immersed" \
  --exe particles="$wrapper" --set run.output.dir="$out" --set fluid.ranks=1 --set immersed.ranks=1 \
  --set particles.ranks=2 --set coupling.timeout=30 >"$out.log" 2>&1
rc=$?
elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
echo "exit status $rc after $elapsed_ms ms"
[ $rc -ne 124 ] || { echo "FAIL: hung (killed after 60 s)"; tail -n 20 "$out.log"; exit 1; }
[ $rc -eq 2 ] || { echo "FAIL: exit status $rc, not 2"; exit 1; }
[ "$elapsed_ms" -le 20000 ] || { echo "FAIL: took longer than 20 s (coupling.timeout is 30 s)"; exit 1; }
grep -qF "$out.missing.yaml" "$out.log" || { echo "FAIL: the rank's message (naming the missing file) is not in $out.log"; tail -n 20 "$out.log"; exit 1; }
grep -qF "run failed in component 'particles' (rank 2): $out.missing.yaml" "$out.log" || { echo "FAIL: the launcher does not name the component and rank with the message"; exit 1; }
echo "ok"
