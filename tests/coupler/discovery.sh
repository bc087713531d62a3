#!/usr/bin/env bash
# discovery.sh BIN_DIR CONFIG OUT
# A wrong launch must stop every rank with a clear message and a non-zero exit,
# quickly (never a hang): a component missing, a component launched twice,
# components reading different configurations, rank counts that differ from
# the YAML, components built with different protocol versions.
set -u
bin=$1 cfg=$2 out=$3
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
mkdir -p "$out"
f="$bin/coflow-dummy-fluid" i="$bin/coflow-dummy-immersed" p="$bin/coflow-dummy-particles"
other="$out/other.yaml"
sed 's/end_time: 0.3 /end_time: 0.4 /' "$cfg" >"$other"
status=0
expect() {  # expect NAME MESSAGE -- mpirun args
  local name=$1 msg=$2; shift 3
  local start=$(date +%s%N)
  timeout 30 mpirun --oversubscribe "$@" >"$out/$name.log" 2>&1
  local rc=$? ms=$(( ($(date +%s%N) - start) / 1000000 ))
  if [ $rc -eq 0 ] || [ $rc -eq 124 ]; then echo "FAIL $name: exit $rc (0 = ran, 124 = hung)"; status=1; return; fi
  if ! grep -qF "$msg" "$out/$name.log"; then echo "FAIL $name: message '$msg' not found"; tail -n 5 "$out/$name.log"; status=1; return; fi
  echo "ok $name: exit $rc in $ms ms: $msg"
}
expect missing "the configuration has a 'immersed' section but coflow-immersed was not launched" -- \
  -np 2 "$f" "$cfg" : -np 1 "$p" "$cfg"
expect twice "component 'fluid' was launched twice" -- \
  -np 2 "$f" "$cfg" : -np 2 "$f" "$cfg" : -np 3 "$i" "$cfg" : -np 1 "$p" "$cfg"
expect configs "components read different configurations" -- \
  -np 2 "$f" "$cfg" : -np 3 "$i" "$other" : -np 1 "$p" "$cfg"
expect ranks "immersed.ranks is 3 in the configuration but 2 ranks were launched" -- \
  -np 2 "$f" "$cfg" : -np 2 "$i" "$cfg" : -np 1 "$p" "$cfg"
expect protocol "coupling protocol version" -- \
  -np 2 env COFLOW_DUMMY_PROTOCOL=1 "$f" "$cfg" : -np 3 "$i" "$cfg" : -np 1 "$p" "$cfg"
exit $status
