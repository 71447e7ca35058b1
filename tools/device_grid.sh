#!/bin/bash
# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
# Resume the full model grid (bench/results/compare_gpu_full) on a lent GPU for at
# most LIMIT_S seconds, then pack the grid into $OUT/grid.tgz, finished or not.
#
# Its data, rebuilt here first and checked against the grid's digests (data_recipe in the
# grid's run.json; about 6 min on two cores):
#   .venv/bin/python bench/bench_compare.py --grid compare_gpu_full --recordings 20 \
#     --windows 128,256,512 --sweeps 85 --code 0452b931b1a4 --data-only --work W
#   .venv/bin/python tools/device_bundle.py --data W/sim128_first20.npz \
#     W/sim256_first20.npz W/sim512_first20.npz
# Then, carrying .device:
#   run(command='bash .device/run.sh bash tools/device_grid.sh 490', carry=['.device'],
#       timeout_s=600)
# LIMIT_S, the 60 s after it and run.sh's install (once per fresh machine) must end
# inside timeout_s, or nothing comes back. Unpack what returns into bench/results/ before
# the next call (a call's tree comes from this checkout). SIGINT stops the grid with its
# finished cells and report kept; the 60 s before SIGKILL let it write run.json.
set -uo pipefail
limit="${1:-}"
if ! [[ "$limit" =~ ^[1-9][0-9]*$ ]]; then
  echo "error: LIMIT_S '$limit': give the seconds the grid may run, a whole number" >&2
  exit 1
fi
for window in 128 256 512; do
  if [ ! -f ".device/data/sim${window}_first20.npz" ]; then
    echo "error: .device/data/sim${window}_first20.npz is missing: build the bundle with" \
      "the grid's datasets (this script's header lists the steps)" >&2
    exit 1
  fi
done
timeout -k 60 -s INT "$limit" python3 bench/bench_compare.py --grid compare_gpu_full \
  --work .device/data --recordings 20 --windows 128,256,512 --cv both --folds 5 --seeds 1 \
  --epochs 100 --early-stopping 30 --profile modern --scaling window --device cuda \
  --cells-per-gpu 16 --cpus 16 --mps
status=$?
# Cells stopped part way keep their training state in the grid's training_state/ (ignored
# by git): it stays on the machine for a next call while it is warm, and does not come back.
tar czf "${OUT:?OUT names the folder whose files come back}/grid.tgz" \
  --exclude=training_state bench/results/compare_gpu_full
exit "$status"
