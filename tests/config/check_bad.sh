#!/usr/bin/env bash
# Usage: check_bad.sh CONFIG COFLOW [COFLOW ...]
# A COFLOW that is not there (the sanitizer build, when it was not made) makes
# the test report itself skipped (exit 77, ctest's SKIP_RETURN_CODE), not passed.
# The config must be rejected by `coflow validate` with exit status 2 and the
# message of its first line ("# expect: :LINE:COL: key.path: message"), and the
# launcher must neither crash nor trip a sanitizer. Lines "# also: TEXT" right
# after it name more text the message must hold (past a part that varies, such
# as an absolute path); a line "# lines: N" there, how many lines the whole
# report must have (one problem must not set off others).
set -u
cfg=$1; shift
expect=$(head -n 1 "$cfg" | sed -n 's/^# expect: //p')
[ -n "$expect" ] || { echo "FAIL: $cfg has no '# expect:' first line"; exit 1; }
mapfile -t also < <(sed -n '2,/^[^#]/s/^# also: //p' "$cfg")
lines=$(sed -n '2,/^[^#]/s/^# lines: //p' "$cfg")
dir=$(dirname "$cfg"); base=$(basename "$cfg")
export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
status=0
skipped=0
for bin in "$@"; do
  [ -x "$bin" ] || { echo "SKIP: $bin is not built"; skipped=1; continue; }
  out=$(cd "$dir" && "$bin" validate "$base" 2>&1 >/dev/null); rc=$?
  if [ $rc -ne 2 ]; then echo "FAIL ($bin): exit status $rc, expected 2"; echo "$out"; status=1; continue; fi
  case "$out" in
    *"$base$expect"*) ;;
    *) echo "FAIL ($bin): message not found"; echo "  expected: $base$expect"; echo "  got:      $out"; status=1 ;;
  esac
  if [ -n "$lines" ] && [ "$(printf '%s\n' "$out" | wc -l)" -ne "$lines" ]; then
    echo "FAIL ($bin): expected $lines line(s) of report, got:"; echo "$out"; status=1
  fi
  for text in "${also[@]}"; do
    case "$out" in
      *"$text"*) ;;
      *) echo "FAIL ($bin): message lacks '$text'"; echo "  got:      $out"; status=1 ;;
    esac
  done
  case "$out" in *Sanitizer*|*"runtime error"*|*terminate*|*HDF5-DIAG*) echo "FAIL ($bin): crash, sanitizer report or a library's raw error stack"; echo "$out"; status=1 ;; esac
done
[ $status -eq 0 ] && [ $skipped -eq 1 ] && exit 77
exit $status
