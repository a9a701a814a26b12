#!/usr/bin/env bash
# Runs one libFuzzer harness once and reports the outcome in one line; on a finding, also the
# report, the input and how to replay it. Used by scripts/fuzz for time-bounded campaigns and
# by the fuzz build's ctest tests (fixed seed, fixed number of runs: CI).
#
#   run_fuzzer.sh [--reproducible] BINARY SEED_DIR OUT_DIR [libFuzzer flags...]
#
# The seeds (SEED_DIR/*, read only) are passed with -seed_inputs in name order and new inputs
# go to a fresh temp folder, so the repo never gets new files and libFuzzer's corpus order does
# not depend on the order a file system lists a folder in.
# --reproducible (with -seed=N -runs=M): the same inputs in the same order on every run and
# machine, so a finding in CI is found again by the same command. Heap and stack addresses
# otherwise steer the fuzzer: comparison tracing puts compared pointers (every iterator loop)
# into its mutation dictionary, a few inlined library branches (shared_ptr release) depend on
# addresses, and the once-a-second corpus reload is timed. So this mode turns off address
# randomisation for the fuzzer (setarch -R, where the kernel allows it; said if not),
# comparison tracing (-use_cmp=0) and the reload (-reload=0). Coverage feedback stays on.
# OUT_DIR gets <harness>.log (libFuzzer's output), <harness>.summary (the summary line) and
# <harness>/ (crash, leak, timeout and out-of-memory inputs). Exit status: libFuzzer's (0:
# nothing found).
set -uo pipefail
runner=("$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/$(basename "${BASH_SOURCE[0]}")" "$@")
reproducible=0
if [ "${1:-}" = "--reproducible" ]; then reproducible=1; shift; fi
if [ $# -lt 3 ]; then
  echo "usage: run_fuzzer.sh [--reproducible] BINARY SEED_DIR OUT_DIR [libFuzzer flags...]" >&2
  exit 2
fi
binary="$1"; seed_dir="$2"; out="$3"; shift 3
h="$(basename "${binary}")"
artifacts="${out}/${h}"
log="${out}/${h}.log"
summary_file="${out}/${h}.summary"
mkdir -p "${artifacts}"
rm -f "${summary_file}"
if [ ! -x "${binary}" ]; then
  echo "${h}: FAILED: ${binary} is not built" | tee "${summary_file}"
  exit 1
fi

work="$(mktemp -d "/tmp/wp_fuzz_${h}.XXXXXX")"
trap 'rm -rf "${work}"' EXIT
seeds=""
if [ -d "${seed_dir}" ]; then
  while IFS= read -r f; do seeds+="${seeds:+,}${f}"; done \
    < <(find "${seed_dir}" -maxdepth 1 -type f -size +0 | LC_ALL=C sort)
fi
# The build uses -fno-sanitize-recover=all, so the first ASan or UBSan report ends the run;
# LeakSanitizer checks every input that allocated more than it freed.
export ASAN_OPTIONS="${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"

launcher=()
mode_flags=()
note=""
if [ ${reproducible} -eq 1 ]; then
  mode_flags=(-use_cmp=0 -reload=0)
  if setarch "$(uname -m)" -R true 2>/dev/null; then
    launcher=(setarch "$(uname -m)" -R)
  else
    note=" (address randomisation could not be turned off here: this run may not repeat exactly)"
  fi
fi

started=${SECONDS}
"${launcher[@]}" "${binary}" -rss_limit_mb=2048 -timeout=30 -print_final_stats=1 \
  -artifact_prefix="${artifacts}/" ${seeds:+-seed_inputs="${seeds}"} "${mode_flags[@]}" "$@" \
  "${work}" >"${log}" 2>&1
rc=$?
elapsed=$(( SECONDS - started ))

execs="$(sed -n 's/^stat::number_of_executed_units: *//p' "${log}" | tail -1)"
cov_line="$(grep -E '^#[0-9]+.*cov: ' "${log}" | tail -1)"
cov="$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"${cov_line}")"
ft="$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"${cov_line}")"
corp="$(sed -n 's/.* corp: \([0-9]*\).*/\1/p' <<<"${cov_line}")"
seed="$(sed -n 's/^INFO: Seed: \([0-9]*\).*/\1/p' "${log}" | head -1)"
if [ -z "${execs}" ]; then execs="$(sed -n 's/^#\([0-9]*\).*/\1/p' <<<"${cov_line}")"; fi
line="${h}: ${execs:-?} executions, ${cov:-?} coverage edges, ${ft:-?} features, corpus ${corp:-?}, seed ${seed:-?}, ${elapsed} s${note}"

if [ ${rc} -eq 0 ]; then
  echo "${line}: ok" | tee "${summary_file}"
  exit 0
fi

report_re='ERROR: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|libFuzzer)|runtime error|INVARIANT VIOLATED|terminate called|ALARM: working on the last Unit'
reason="$(grep -m1 -E "${report_re}" "${log}" | sed 's/^==[0-9]*== *//')"
artifact="$(grep -o 'Test unit written to .*' "${log}" | tail -1 | sed 's/Test unit written to //')"
{
  echo "${line}: FAILED (exit ${rc}): ${reason:-see ${log}}"
  if [ -n "${artifact}" ]; then
    echo "  input:  ${artifact}"
    echo "  replay: ${binary} ${artifact}   (WP_FUZZ_TRACE=1 prints every operation)"
  fi
  echo "  log:    ${log}"
  echo "  rerun:  $(printf '%q ' "${runner[@]}")"
} | tee "${summary_file}"
# The report itself, so that a CI log alone says what happened (the input as Base64 too).
echo "---- ${h}: report (from ${log}) ----"
first="$(grep -n -m1 -E "${report_re}" "${log}" | cut -d: -f1)"
if [ -n "${first}" ]; then
  # From the report's first line to its SUMMARY line (at most 80 lines): the stacks, not the
  # shadow-byte map.
  last="$(awk -v f="${first}" 'NR >= f && /^SUMMARY: /{print NR; exit}' "${log}")"
  if [ -z "${last}" ] || [ "${last}" -gt $(( first + 80 )) ]; then last=$(( first + 80 )); fi
  sed -n "${first},${last}p" "${log}"
else
  tail -n 60 "${log}"
fi
grep -m1 '^Base64: ' "${log}" || true
echo "---- end of ${h} report ----"
exit ${rc}
