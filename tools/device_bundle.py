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
  Java jars, RLlib, Data, Serve, Train, Tune, LLM and the dashboard's web client) and
  with its programs' symbol tables stripped, about a fifth of the wheel;
- data.tar.xz: the files given with --data (a dataset's .json sidecar with its .npz),
  which run.sh unpacks into data/ there;
- run.sh: installs the above into /tmp/site (again when the bundle changed; whole or
  not at all), checks that the image has what Ray and tactex need besides, puts `src/*`
  on PYTHONPATH, writes a `tactex` script beside the image's python3, and runs its
  arguments;
- .tactex-device-bundle: the mark of a bundle this tool wrote, listing its files.
OUT is built in a temporary folder beside it and renamed into place only when whole: an
earlier bundle (marked, and holding no file the mark does not list) is replaced then, and
left as it was when a step fails. Any other existing OUT, or a symbolic link, is refused.
It prints the bundle's size with the working tree's (a call carries both, 64 MiB in all)
and fails when they do not fit. Then, for example:
    .venv/bin/python tools/device_bundle.py --data /tmp/tactex-compare-data/sim128_first20.npz
    run(command='bash .device/run.sh python3 bench/bench_gpu_pace.py --data '
                '.device/data/sim128_first20.npz --out $OUT/gpu_pace.json',
        carry=['.device'])
"""

from __future__ import annotations

import argparse
import importlib.metadata
import io
from pathlib import Path
import shutil
import subprocess
import sys
import tarfile
import tempfile
import time
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
ELF_MAGIC = b'\x7fELF'
# Written last into a bundle, this line and the files written: what tells an earlier bundle
# (replaced whole) from a user's folder or files.
MARK = '.tactex-device-bundle'
MARK_LINE = 'written by tools/device_bundle.py; rebuilt whole on each run'
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
if [ -f "$here/data.tar.xz" ]; then  # the --data files, as the bundle was built with them
  mkdir -p "$here/data"
  tar -xJf "$here/data.tar.xz" -C "$here/data"
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


class BundleError(Exception):
    """A step of writing the bundle failed; the message says which and what to do."""


def pinned(name: str) -> str:
    """`name`==the version installed here."""
    try:
        return f'{name}=={importlib.metadata.version(name)}'
    except importlib.metadata.PackageNotFoundError:
        raise BundleError(f'{name} is not installed in this environment, so its version is '
                          'unknown; install requirements.txt into .venv') from None


def download(names: list[str], into: Path) -> None:
    """CPython 3.12 manylinux wheels of `names` (pinned specs) into `into`, no dependencies."""
    platforms = [option for name in PLATFORMS for option in ('--platform', name)]
    pip = subprocess.run([sys.executable, '-m', 'pip', 'download', '-q', '--no-deps',
                          '--only-binary=:all:', '--python-version', '3.12', '--implementation',
                          'cp', *platforms, '-d', str(into), *names],
                         stderr=subprocess.PIPE, text=True, check=False)
    if pip.returncode:
        last = (pip.stderr.strip().splitlines() or ['(no message)'])[-1].strip()
        what = names[0] if len(names) == 1 else f'{len(names)} packages'
        raise BundleError(f'downloading wheels for cp312 ({what}) failed (pip exited '
                          f'{pip.returncode}): {last}; check the package index is reachable')


def strip_elf_files(folder: Path) -> None:
    """Strip the symbol tables Ray's programs and libraries ship with (a third of its size).

    `strip --strip-unneeded` keeps what loading and linking need (the dynamic symbols, a
    Python extension's PyInit_), so only stack traces read less: Ray's raylet, GCS server
    and _raylet.so go from 120 to 84 MB, its xz archive from 27.6 to 18.3 MB.
    """
    binaries = [str(path) for path in sorted(folder.rglob('*'))
                if path.is_file() and not path.is_symlink() and _starts_with_elf_magic(path)]
    if not binaries:
        return
    strip = subprocess.run(['strip', '--strip-unneeded', *binaries], stderr=subprocess.PIPE,
                           text=True, check=False)
    if strip.returncode:
        last = (strip.stderr.strip().splitlines() or ['(no message)'])[-1].strip()
        raise BundleError(f"stripping Ray's programs failed (strip exited {strip.returncode}): "
                          f'{last}')


def _starts_with_elf_magic(path: Path) -> bool:
    with path.open('rb') as handle:
        return handle.read(len(ELF_MAGIC)) == ELF_MAGIC


def trimmed_ray(into: Path) -> Path:
    """Ray's pinned wheel unpacked without RAY_UNUSED, as `into`/ray.tar.xz."""
    with tempfile.TemporaryDirectory(prefix='ray-wheel-') as folder:
        folder = Path(folder)
        download([pinned('ray')], folder)
        (wheel,) = folder.glob('ray-*.whl')
        unpacked = folder / 'site'
        with zipfile.ZipFile(wheel) as archive:
            archive.extractall(unpacked)
        for part in RAY_UNUSED:
            shutil.rmtree(unpacked / part)
        for binary in (unpacked / 'ray' / 'core').rglob('*'):
            if binary.is_file() and binary.suffix == '':
                binary.chmod(0o755)  # zip archives keep no modes: raylet, gcs_server
        strip_elf_files(unpacked)
        target = into / 'ray.tar.xz'
        with tarfile.open(target, 'w:xz', preset=9) as archive:  # 64 MiB window
            for path in sorted(unpacked.iterdir()):
                archive.add(path, arcname=path.name)
    return target


def ignore(folder: Path) -> None:
    """Add `folder` to this checkout's .git/info/exclude (a worktree's too) if inside it."""
    if not folder.resolve().is_relative_to(ROOT):
        return
    entry = f'/{folder.resolve().relative_to(ROOT)}/'
    git = subprocess.run(['git', 'rev-parse', '--git-path', 'info/exclude'], cwd=ROOT,
                         capture_output=True, text=True, check=False)
    if git.returncode:
        return  # no git checkout: nothing to exclude from
    exclude = (ROOT / git.stdout.strip()).resolve()
    exclude.parent.mkdir(parents=True, exist_ok=True)
    known = exclude.read_text(encoding='utf-8').splitlines() if exclude.is_file() else []
    if entry not in known:
        with exclude.open('a', encoding='utf-8') as handle:
            handle.write(entry + '\n')


def files(folder: Path) -> set[str]:
    """The paths of what is under `folder` but folders, relative to it."""
    return {str(path.relative_to(folder)) for path in folder.rglob('*')
            if path.is_symlink() or not path.is_dir()}


def check(out: Path, data: list[Path]) -> None:
    """Raise BundleError saying what is wrong with the arguments, before anything is written."""
    for path in data:
        if path.is_dir():
            raise BundleError(f'--data {path} is a folder; give the files the device command '
                              'reads (a dataset .npz, its .json sidecar beside it; a bag file)')
    missing = [str(path) for path in data if not path.is_file()]
    if missing:
        raise BundleError(f'--data {", ".join(missing)}: no such file')
    names = [path.name for path in data]
    if twice := sorted({name for name in names if names.count(name) > 1}):
        raise BundleError(f'--data names {", ".join(twice)} more than once (the files land in '
                          'one folder there); give each file once, renamed if need be')
    if shutil.which('strip') is None:
        raise BundleError('strip is not installed, and Ray unstripped leaves too little of '
                          'what a call carries; install binutils (apt-get install binutils)')
    if out.is_symlink():
        raise BundleError(f'--out {out} is a symbolic link, which this tool does not follow '
                          '(it replaces --out whole); give the folder itself or a new one')
    if out.exists():
        mark = out / MARK
        listed = mark.read_text(errors='replace').splitlines() if mark.is_file() else []
        if not out.is_dir() or listed[:1] != [MARK_LINE]:
            raise BundleError(f'--out {out} exists and is no bundle of this tool (it has no '
                              f'{MARK}); give a new folder, or remove that one yourself')
        if extra := sorted(files(out) - {MARK, *listed[1:]}):
            raise BundleError(f'--out {out} holds files this tool did not write '
                              f'({", ".join(extra[:3])}); move them out or give a new folder')
    if not out.parent.is_dir():
        raise BundleError(f'--out {out}: its folder {out.parent} does not exist; create it')


def pack_data(data: list[Path], target: Path) -> None:
    """The --data files (a dataset's .json sidecar with its .npz) in one xz archive.

    A dataset (.npz) goes in with its members stored, not deflated, so xz compresses the
    arrays themselves, across datasets too: the full grid's three (one set of sweeps cut at
    three windows) take 3.4 MB instead of 15.4. The same arrays come out (a dataset's digest
    is of its arrays, not of its file's bytes).
    """
    with tarfile.open(target, 'w:xz', preset=9) as archive:
        for path in data:
            sidecar = path.with_suffix('.json')  # a dataset's classes, channels and origin
            for member in [path, *([sidecar] if path.suffix == '.npz' and sidecar.is_file()
                                   else [])]:
                content = (_stored(member) if member.suffix == '.npz'
                           and zipfile.is_zipfile(member) else member.read_bytes())
                entry = tarfile.TarInfo(member.name)
                entry.size, entry.mode, entry.mtime = len(content), 0o644, int(time.time())
                archive.addfile(entry, io.BytesIO(content))


def _stored(path: Path) -> bytes:
    """The zip archive at `path` again, its members stored without compression."""
    buffer = io.BytesIO()
    with zipfile.ZipFile(path) as source, zipfile.ZipFile(buffer, 'w') as copy:
        for member in source.infolist():
            copy.writestr(member.filename, source.read(member),
                          compress_type=zipfile.ZIP_STORED)
    return buffer.getvalue()


def build(into: Path, data: list[Path]) -> None:
    """Write the bundle's files into the empty folder `into`, its mark last."""
    (into / 'wheels').mkdir()
    download([pinned(name) for name in PACKAGES], into / 'wheels')
    trimmed_ray(into)
    if data:
        pack_data(data, into / 'data.tar.xz')
    (into / 'run.sh').write_text(RUN_SH, encoding='utf-8')
    (into / 'run.sh').chmod(0o755)
    (into / MARK).write_text('\n'.join([MARK_LINE, *sorted(files(into))]) + '\n',
                             encoding='utf-8')


def replace(out: Path, new: Path) -> None:
    """Rename the whole bundle `new` to `out`; an earlier bundle there is removed only then."""
    old = new.with_name(new.name + '.old')
    if out.exists():
        out.rename(old)
    try:
        new.rename(out)
    except OSError:
        if old.exists():
            old.rename(out)
        raise
    shutil.rmtree(old, ignore_errors=True)


def write(out: Path, data: list[Path]) -> None:
    """Build the bundle beside `out` (same folder: the rename is atomic), then put it there."""
    work = Path(tempfile.mkdtemp(prefix=f'.{out.name}.', suffix='.partial', dir=out.parent))
    try:
        work.chmod(0o755)  # mkdtemp's is 0o700
        build(work, data)
        ignore(out)
        replace(out, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)  # gone already when it was put in place


def working_tree_bytes() -> int | None:
    """The size of what a call sends besides carried paths: tracked and unignored files."""
    git = subprocess.run(['git', 'ls-files', '-z', '--cached', '--others', '--exclude-standard'],
                         cwd=ROOT, capture_output=True, check=False)
    if git.returncode:
        return None  # no git checkout: the tree cannot be told from what is ignored
    paths = (ROOT / name for name in git.stdout.decode().split('\0') if name)
    return sum(path.stat().st_size for path in paths if path.is_file() and not path.is_symlink())


def main() -> int:
    """Write the bundle; print its size against what a call may carry."""
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--out', type=Path, default=ROOT / '.device')
    parser.add_argument('--data', type=Path, nargs='*', default=[],
                        help='files the device command reads (datasets, bags)')
    args = parser.parse_args()
    try:
        check(args.out, args.data)
        write(args.out, args.data)
    except BundleError as failure:
        print(f'error: {failure}', file=sys.stderr)
        return 1
    except OSError as failure:
        print(f'error: writing the bundle {args.out} failed: {failure}; {args.out} is as it '
              'was', file=sys.stderr)
        return 1
    size = sum(path.stat().st_size for path in args.out.rglob('*') if path.is_file())
    tree = working_tree_bytes()
    if tree is None:
        print(f'{args.out}: {size / 2**20:.1f} MiB of the {CARRY_LIMIT // 2**20} MiB a call '
              'carries (the working tree counts too)')
        return 0
    total = size + tree
    if total > CARRY_LIMIT:
        fix = ('give fewer or smaller --data files' if tree < CARRY_LIMIT else
               'the working tree alone is too big: ignore or remove untracked files')
        print(f'error: {args.out} ({size / 2**20:.1f} MiB, written) and the working tree '
              f'({tree / 2**20:.1f} MiB) make {total / 2**20:.1f} MiB, over the '
              f'{CARRY_LIMIT // 2**20} MiB a call carries; {fix}', file=sys.stderr)
        return 1
    print(f'{args.out}: {size / 2**20:.1f} MiB; with the working tree ({tree / 2**20:.1f} '
          f'MiB) a call carries {total / 2**20:.1f} of its {CARRY_LIMIT // 2**20} MiB')
    return 0


if __name__ == '__main__':
    sys.exit(main())
