# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Pack what a lent GPU machine lacks to run tactex there: wheels, a trimmed Ray, the data.

The lent machine's image has Python 3.12 with torch, numpy, scikit-learn and matplotlib
but not Ray or the recording libraries tactex imports, reaches no package index, and a
call may carry 64 MiB. This writes OUT (default `.device/` in the checkout, which it adds
to .git/info/exclude) with:
- wheels/: CPython 3.12 wheels of the packages the image lacks, at the versions installed
  here (requirements.txt pins the direct ones);
- ray.tar.xz: Ray at its pinned version, unpacked without what tactex never imports (its
  Java jars, RLlib, Data, Serve, Train, Tune, LLM and the dashboard's web client), about
  a third of the wheel;
- data/: the files given with --data (a dataset's .json sidecar with its .npz);
- run.sh: installs the above into /tmp/site (again when the bundle changed; whole or
  not at all), checks that the image has what Ray and tactex need besides, puts `src/*`
  on PYTHONPATH, writes a `tactex` script beside the image's python3, and runs its
  arguments.
Then, for example:
    .venv/bin/python tools/device_bundle.py --data /tmp/tactex-compare-data/sim128_first20.npz
    run(command='bash .device/run.sh python3 bench/bench_gpu_pace.py --data '
                '.device/data/sim128_first20.npz --out $OUT/gpu_pace.json',
        carry=['.device'])
"""

from __future__ import annotations

import argparse
import importlib.metadata
from pathlib import Path
import shutil
import subprocess
import sys
import tarfile
import tempfile
import zipfile

ROOT = Path(__file__).resolve().parents[1]
# What tactex imports that the image lacks: Ray's needs, the recording readers', plotting's.
# The image's own (torch, numpy, Ray's msgpack, protobuf, click, ...) run.sh checks.
PACKAGES = ('rosbags', 'lz4', 'ruamel.yaml', 'apsw', 'backports.zstd', 'transforms3d',
            'adjustText', 'jsonschema', 'jsonschema-specifications', 'referencing', 'rpds-py')
# Ray's parts that neither tactex nor Ray's core (a local instance, tasks) imports.
RAY_UNUSED = ('ray/jars', 'ray/rllib', 'ray/data', 'ray/serve', 'ray/train', 'ray/tune',
              'ray/llm', 'ray/dashboard/client')
PLATFORMS = ('manylinux_2_28_x86_64', 'manylinux_2_27_x86_64', 'manylinux_2_17_x86_64',
             'manylinux2014_x86_64', 'manylinux1_x86_64')
CARRY_LIMIT = 64 * 2**20
RUN_SH = r"""#!/bin/bash
# Written by tools/device_bundle.py: install what the image lacks (again when the bundle
# changed), then run the arguments with tactex importable and a `tactex` script.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(dirname "$here")"
site=/tmp/site
stamp="$(cat "$here/ray.tar.xz" "$here"/wheels/*.whl | sha256sum | cut -d' ' -f1)"
if [ "$(cat "$site/.bundle" 2>/dev/null || true)" != "$stamp" ]; then
  rm -rf "$site" "$site.partial"
  python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir \
    --target "$site.partial" "$here"/wheels/*.whl
  tar -xJf "$here/ray.tar.xz" -C "$site.partial"
  echo "$stamp" > "$site.partial/.bundle"
  mv "$site.partial" "$site"
fi
export PYTHONPATH="$site:$(ls -d "$repo"/src/*/ | tr '\n' ':')${PYTHONPATH:-}"
export PYTHONPATH="${PYTHONPATH%:}"
python3 -c 'import ray, msgpack, google.protobuf, click, yaml, requests, filelock, torch'
export PYTHONUNBUFFERED=1
bin="$(python3 -c 'import os, sys; print(os.path.dirname(sys.executable))')"
printf '#!/bin/sh\nexec "%s" -m tactex "$@"\n' "$bin/python3" > "$bin/tactex"
chmod +x "$bin/tactex"
export PATH="$bin:$PATH"
cd "$repo"
exec "$@"
"""


def download(names: list[str], into: Path) -> None:
    """CPython 3.12 manylinux wheels of `names` (pinned specs) into `into`, no dependencies."""
    platforms = [option for name in PLATFORMS for option in ('--platform', name)]
    subprocess.run([sys.executable, '-m', 'pip', 'download', '-q', '--no-deps',
                    '--only-binary=:all:', '--python-version', '3.12', '--implementation',
                    'cp', *platforms, '-d', str(into), *names], check=True)


def trimmed_ray(into: Path) -> Path:
    """Ray's pinned wheel unpacked without RAY_UNUSED, as `into`/ray.tar.xz."""
    with tempfile.TemporaryDirectory(prefix='ray-wheel-') as folder:
        folder = Path(folder)
        download([f'ray=={importlib.metadata.version("ray")}'], folder)
        (wheel,) = folder.glob('ray-*.whl')
        unpacked = folder / 'site'
        with zipfile.ZipFile(wheel) as archive:
            archive.extractall(unpacked)
        for part in RAY_UNUSED:
            shutil.rmtree(unpacked / part)
        for binary in (unpacked / 'ray' / 'core').rglob('*'):
            if binary.is_file() and binary.suffix == '':
                binary.chmod(0o755)  # zip archives keep no modes: raylet, gcs_server
        target = into / 'ray.tar.xz'
        with tarfile.open(target, 'w:xz') as archive:
            for path in sorted(unpacked.iterdir()):
                archive.add(path, arcname=path.name)
    return target


def ignore(folder: Path) -> None:
    """Add `folder` to this checkout's .git/info/exclude (a worktree's too) if inside it."""
    if not folder.resolve().is_relative_to(ROOT):
        return
    entry = f'/{folder.resolve().relative_to(ROOT)}/'
    found = subprocess.run(['git', 'rev-parse', '--git-path', 'info/exclude'], cwd=ROOT,
                           capture_output=True, text=True, check=True).stdout.strip()
    exclude = (ROOT / found).resolve()
    exclude.parent.mkdir(parents=True, exist_ok=True)
    known = exclude.read_text(encoding='utf-8').splitlines() if exclude.is_file() else []
    if entry not in known:
        with exclude.open('a', encoding='utf-8') as handle:
            handle.write(entry + '\n')


def main() -> int:
    """Write the bundle; print its size against what a call may carry."""
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--out', type=Path, default=ROOT / '.device')
    parser.add_argument('--data', type=Path, nargs='*', default=[],
                        help='files the device command reads (datasets, bags)')
    args = parser.parse_args()
    missing = [str(path) for path in args.data if not path.is_file()]
    if missing:
        print(f'error: --data {", ".join(missing)}: no such file', file=sys.stderr)
        return 1
    if args.out.exists():
        if not (args.out / 'run.sh').is_file() or not args.out.is_dir():
            print(f'error: --out {args.out} exists and is no bundle of this tool; give a new '
                  'folder', file=sys.stderr)
            return 1
        shutil.rmtree(args.out)  # an earlier bundle: written again whole
    (args.out / 'wheels').mkdir(parents=True)
    download([f'{name}=={importlib.metadata.version(name)}' for name in PACKAGES],
             args.out / 'wheels')
    trimmed_ray(args.out)
    (args.out / 'data').mkdir()
    for path in args.data:
        shutil.copy2(path, args.out / 'data' / path.name)
        sidecar = path.with_suffix('.json')  # a dataset's classes, channels and origin
        if path.suffix == '.npz' and sidecar.is_file():
            shutil.copy2(sidecar, args.out / 'data' / sidecar.name)
    (args.out / 'run.sh').write_text(RUN_SH, encoding='utf-8')
    (args.out / 'run.sh').chmod(0o755)
    ignore(args.out)
    size = sum(path.stat().st_size for path in args.out.rglob('*') if path.is_file())
    print(f'{args.out}: {size / 2**20:.1f} MiB of the {CARRY_LIMIT // 2**20} MiB a call '
          'carries (the working tree counts too)')
    return 0


if __name__ == '__main__':
    sys.exit(main())
