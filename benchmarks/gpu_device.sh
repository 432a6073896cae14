#!/usr/bin/env bash
# Issue 38's device check in one call of at most 8 minutes on one H100 or H200 (docs/performance.md,
# "The device check"): every part of benchmarks/gpu.py in order -- env, compile, agree (4 variants,
# each in its own process; numba-cuda's disk cache then serves the later parts' compiles), steps,
# fig4, fig4 --until-steady 0.02, the paper's 1,080 cases to their end or to the budget, the largest
# bed -- its JSON written after every part into $OUT/gpu.json, a summary in $OUT/gpu.md.
# Before: `bash benchmarks/gpu_wheels.sh` here (the wheels the GPU machines lack, into .whl/), and
# the device tool's `carry` names .whl. The parts are bounded by --budget-s (the paper stops there
# and says how far it got); fig4 runs to its end.
set -uo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-/tmp/pdamper-gpu}
mkdir -p "$OUT"
if ls .whl/*.whl >/dev/null 2>&1; then
    pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl
fi
export PYTHONPATH=/tmp/site:$PWD/src PYTHONUNBUFFERED=1
nvidia-smi --query-gpu=name,clocks.max.sm,memory.total --format=csv,noheader || true
timeout 470 python benchmarks/gpu.py --out "$OUT/gpu.json" --budget-s 400 --steps-seconds 6 --bed-seconds 10
echo "exit $?"
