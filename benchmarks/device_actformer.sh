#!/usr/bin/env bash
# The ActFormer benchmark on a GPU machine, run from the repository root with OUT set to the folder that comes
# back: both sides on the GPU (jaxmotion on JAX's CUDA backend, the PyTorch peer on cuda), float32 with matmul
# precision "highest" / TF32 off; the table goes to $OUT/bench_actformer_h200.txt, the rows to the .json beside it.
# `timeout` keeps the run under 8 minutes; the JSON is rewritten after each part, so a cut run keeps its train row.
set -euo pipefail
export PYTHONUNBUFFERED=1
: "${OUT:?set OUT to the output folder}"
mkdir -p "$OUT"
nvidia-smi -L
python3 -c "import sys, jax, jaxlib, torch; print('python', sys.version.split()[0]); \
print('jax', jax.__version__, 'jaxlib', jaxlib.__version__, jax.devices()); \
print('torch', torch.__version__, 'cuda', torch.version.cuda, 'available', torch.cuda.is_available())"
PYTHONPATH=. timeout -k 10 450 python3 benchmarks/bench_actformer.py --repeats 5 --batch 64 --per-class 100 \
    --out "$OUT/bench_actformer_h200.json" 2>&1 | tee "$OUT/bench_actformer_h200.txt"
