#!/usr/bin/env bash
# The one device check (issue 46): bench/gpu_bench.py's stages in order of value, each in its own process under
# what is left of one time budget, so a stage that runs long costs only the stages after it.
#
#   bench/gpu_device_check.sh                    # on a GPU machine (H100/H200, 16 cores): within 8 minutes
#   bench/gpu_device_check.sh --simulate         # no GPU: numba's CUDA simulator, tiny sizes (CI runs this)
#   bench/gpu_device_check.sh --stages "cold 1M" # some stages only
#
# Stages: cold random solves, the 1M example map (with cold: one process, the DB kernels once), the speed map,
# the roller map, the 1e8-case float32 K map (its 10 GB file in a temporary folder, removed at the end).
# Figures: $OUT/gpu-device-check.txt where $OUT is set (the device machine brings $OUT back), else
# bench/gpu-device-check.txt; written afresh on every run. Safe to rerun: the temporary folder goes on exit
# (also on Ctrl-C or a timeout), the file is replaced, numba's cache is kept: the CPU kernels and the CUDA kernels
# (engine/cuda_kernels.py, cache=True), so a rerun compiles nothing; the first run's compiling is in the budget.
# Exit status: 0 when every stage ran and agreed, 1 on a disagreement, 2 when a stage failed or was cut short.
# BUDGET_S (default 480) is the whole check's time; PYTHON (default python) the interpreter.
set -u -o pipefail
cd "$(dirname "$0")/.."

simulate=""
stages="cold,1M speed roller 1e8"
while [ $# -gt 0 ]; do
  case "$1" in
    --simulate) simulate="--simulate" ;;
    --stages) stages="$2"; shift ;;
    *) echo "gpu_device_check.sh: unknown argument $1 (--simulate, --stages \"cold,1M speed\")" >&2; exit 2 ;;
  esac
  shift
done

python_bin="${PYTHON:-python}"
budget="${BUDGET_S:-480}"
figures="${OUT:-bench}/gpu-device-check.txt"
mkdir -p "$(dirname "$figures")"
work="$(mktemp -d "${TMPDIR:-/tmp}/gpu-device-check.XXXXXX")"
trap 'rm -rf "$work"' EXIT INT TERM
start=$(date +%s)
status=0

say() { echo "$*" | tee -a "$figures"; }

: > "$figures"
say "gpu_device_check: $(date -u +%Y-%m-%dT%H:%M:%SZ), budget ${budget} s, stages: ${stages}${simulate:+ (simulator)}"
if [ -z "$simulate" ] && command -v nvidia-smi > /dev/null; then
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv,noheader 2>&1 | tee -a "$figures"
fi
"$python_bin" bench/gpu_bench.py --plan ${simulate:+--small} 2>&1 | tee -a "$figures"

for group in $stages; do
  left=$(( budget - ($(date +%s) - start) ))
  if [ "$left" -lt 20 ]; then
    say "stage ${group}: not run (${left} s of the budget left)"
    status=2
    continue
  fi
  say "stage ${group}: started with ${left} s of the budget left"
  timeout --signal=INT --kill-after=10 "$left" \
    "$python_bin" bench/gpu_bench.py $simulate --only "$group" --folder "$work" 2>&1 | tee -a "$figures"
  rc=${PIPESTATUS[0]}
  case "$rc" in
    0) ;;
    1) status=$(( status > 1 ? status : 1 )) ;;
    124|130|137) say "stage ${group}: cut short at the budget (exit ${rc})"; status=2 ;;
    *) say "stage ${group}: failed (exit ${rc})"; status=2 ;;
  esac
done
say "gpu_device_check: done in $(( $(date +%s) - start )) s, exit ${status}; figures in ${figures}"
exit "$status"
