#!/usr/bin/env bash
# Runs one CLI test (tests/cli_tests.cmake): a command, then checks of its
# exit status, of what it printed and of the files it wrote. CTest's
# PASS_REGULAR_EXPRESSION alone would ignore the exit status.
#
#   run_cli_test.sh --checker MBRT_CLI_CHECK [checks] -- COMMAND [ARGS...]
#     --code N           the exit status expected (default 0)
#     --out REGEX        some line of stdout+stderr matches (grep -E); repeatable
#     --no-out REGEX     no line matches; repeatable
#     --check "ARGS"     MBRT_CLI_CHECK ARGS must succeed afterwards (image, same, rays, hits); repeatable
#     --exists PATH      PATH exists afterwards (a file, or a symlink itself); repeatable
#     --absent PATH      PATH does not exist afterwards; repeatable
#     --no-temp DIR      no temporary output file (.NAME.tmp-XXXXXX) is left in DIR
#     --after "SHELL"    run with bash afterwards; must succeed; repeatable
#     --no-control-codes the output has no carriage return and no escape character
#     --setup "SHELL"    run with bash before the command; must succeed; repeatable
#     --signal SIG REGEX send SIG to the command once a line of its output matches REGEX
#     --require PATH     when PATH is absent, skip: exit 77 with the reason
#     --timeout S        seconds the command may run (default 120)
# Exit 0 when every check holds, 1 otherwise, 77 when skipped.
set -u

checker=""
code=0
timeout_s=120
signal=""
signal_re=""
outs=()
no_outs=()
checks=()
exists=()
absent=()
no_temp=()
setups=()
afters=()
plain=0
while [[ $# -gt 0 && "$1" != "--" ]]; do
  case "$1" in
    --checker) checker="$2"; shift 2 ;;
    --code) code="$2"; shift 2 ;;
    --out) outs+=("$2"); shift 2 ;;
    --no-out) no_outs+=("$2"); shift 2 ;;
    --check) checks+=("$2"); shift 2 ;;
    --exists) exists+=("$2"); shift 2 ;;
    --absent) absent+=("$2"); shift 2 ;;
    --no-temp) no_temp+=("$2"); shift 2 ;;
    --setup) setups+=("$2"); shift 2 ;;
    --after) afters+=("$2"); shift 2 ;;
    --no-control-codes) plain=1; shift ;;
    --signal) signal="$2"; signal_re="$3"; shift 3 ;;
    --require)
      if [[ ! -e "$2" ]]; then echo "skipped: $2 is absent"; exit 77; fi
      shift 2 ;;
    --timeout) timeout_s="$2"; shift 2 ;;
    *) echo "run_cli_test.sh: unknown option '$1'" >&2; exit 1 ;;
  esac
done
if [[ $# -lt 2 || "$1" != "--" ]]; then echo "run_cli_test.sh: no command after --" >&2; exit 1; fi
shift

failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

for s in ${setups[@]+"${setups[@]}"}; do
  if ! bash -c "$s"; then echo "FAIL: setup '$s' failed"; exit 1; fi
done

log=$(mktemp)
trap 'rm -f "$log"' EXIT
echo "\$ $*"
if [[ -n "$signal" ]]; then
  "$@" >"$log" 2>&1 &
  pid=$!
  sent=0
  for ((i = 0; i < timeout_s * 10; ++i)); do
    if ! kill -0 "$pid" 2>/dev/null; then break; fi
    if grep -qE -- "$signal_re" "$log"; then kill -s "$signal" "$pid"; sent=1; break; fi
    sleep 0.1
  done
  if [[ $sent == 0 ]]; then
    kill -s KILL "$pid" 2>/dev/null
    fail "no line matched '$signal_re' while the command ran: SIG$signal not sent"
  fi
  # The timeout covers the whole run, the time after the signal included.
  for (( ; i < timeout_s * 10; ++i)); do
    if ! kill -0 "$pid" 2>/dev/null; then break; fi
    sleep 0.1
  done
  if kill -0 "$pid" 2>/dev/null; then
    kill -s KILL "$pid" 2>/dev/null
    fail "still running ${timeout_s} s after it started (SIG$signal sent): killed"
  fi
  wait "$pid"
  rc=$?
else
  timeout "$timeout_s" "$@" >"$log" 2>&1
  rc=$?
fi
cat "$log"
echo "--- exit status $rc"

[[ "$rc" == "$code" ]] || fail "exit status $rc, expected $code"
for re in ${outs[@]+"${outs[@]}"}; do
  grep -qE -- "$re" "$log" || fail "no line of the output matches '$re'"
done
for re in ${no_outs[@]+"${no_outs[@]}"}; do
  if grep -qE -- "$re" "$log"; then fail "a line of the output matches '$re'"; fi
done
for c in ${checks[@]+"${checks[@]}"}; do
  # shellcheck disable=SC2086  # the check's words are its arguments
  "$checker" $c || fail "check '$c' failed"
done
for p in ${exists[@]+"${exists[@]}"}; do
  [[ -e "$p" || -L "$p" ]] || fail "'$p' does not exist"
done
for p in ${absent[@]+"${absent[@]}"}; do
  if [[ -e "$p" || -L "$p" ]]; then fail "'$p' exists"; fi
done
for d in ${no_temp[@]+"${no_temp[@]}"}; do
  left=$(find "$d" -maxdepth 1 -name '.*.tmp-*' 2>/dev/null)
  [[ -z "$left" ]] || fail "temporary files left in '$d': $left"
done
for a in ${afters[@]+"${afters[@]}"}; do
  bash -c "$a" || fail "'$a' failed afterwards"
done
if [[ $plain == 1 ]] && grep -q $'[\r\033]' "$log"; then fail "the output has a carriage return or an escape character"; fi
if [[ $failures -gt 0 ]]; then exit 1; fi
echo "PASS"
