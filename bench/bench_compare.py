# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The kept model comparisons: the synthetic set, any models and baselines, up to 3 windows.

Collects the synthetic set once (`tactex sim collect`, 12 textures x 25 sweeps, on
`--cpus` Ray workers; or takes `--bags`), keeps the first `--recordings` sweeps of each
texture when asked (whole recordings, hard-linked into their own folder), converts them
at 128, 256 and 512 samples (50 % overlap) into `--work` (datasets already there, such
as those carried to a lent GPU, need no bags), then runs `tactex compare`
on the datasets into bench/results/GRID/ (`--grid`, default compare: five epochs, both
schemes; compare_long: the deep models trained longer; compare_converged: the README's
main comparison; compare_gpu: the lent GPU's first grid; compare_gpu_full: every model
at every window and scheme on a lent GPU). The grid resumes: run this again
(same settings) and only the cells not yet finished are trained, so the kept run can be
built in chunks on a busy machine. Each call appends its steps and their durations to
GRID/run.json; `bench/render_results.py` builds the docs' comparison sections from
summary.json and run.json only.

A grid resumes only on the data it was started with (GRID/grid.json keeps their digests),
and the simulator changes between commits, so the bench notes in GRID/run.json how it
built a grid's data: the commit, sweeps and recordings per texture (`data_recipe`).
`--code COMMIT` collects and converts with the tactex of that commit (a git worktree put
first on PYTHONPATH, removed after; its bags in a folder named by commit and sweeps), and
`--data-only` builds the datasets, checks them against the grid's digests and stops: how
a lent GPU's grid gets its data again on a fresh machine. Only tactex's own packages come
from that commit; the libraries are this environment's.
"""

import argparse
from collections.abc import Iterator
import contextlib
import json
import os
from pathlib import Path
import shutil
import subprocess
import sys
import time

from tactex_classify.data.dataset import Dataset

RESULTS = Path(__file__).parent / 'results'
TACTEX = str(Path(sys.executable).parent / 'tactex')
WINDOWS = (128, 256, 512)


def _timed(command: list[str], steps: list[dict], env: dict | None = None) -> None:
    """Run a command (failing loudly); note its time, the load around it and its exit status.

    A grid interrupted by Ctrl-C (or `timeout -s INT`, which signals the whole process
    group) keeps its finished cells and writes its report: the child is waited for, and
    its time is noted too.
    """
    start, load = time.monotonic(), os.getloadavg()[0]
    returncode = None
    child = subprocess.Popen(command, env=env)
    try:
        returncode = child.wait()
    except KeyboardInterrupt:
        while returncode is None:  # the child had the same signal: let it write its report
            try:
                returncode = child.wait()
            except KeyboardInterrupt:
                pass
        raise
    finally:
        steps.append({'command': ' '.join(['tactex', *command[1:]]),
                      'seconds': round(time.monotonic() - start, 1),
                      'load_average': [round(load, 1), round(os.getloadavg()[0], 1)],
                      'returncode': returncode})
    if returncode:
        raise subprocess.CalledProcessError(returncode, command)


def first_recordings(bags: Path, per_texture: int, work: Path) -> Path:
    """The first `per_texture` recordings of each texture (by name), in a folder of their own.

    Recordings are named `<texture>_<sweep>`; the folder (`<bags' name>_first<N>` in
    `work`) holds hard links to their files and is built whole (a partial folder renamed at
    the end).
    """
    subset = work / f'{bags.name}_first{per_texture}'
    if subset.is_dir():
        return subset
    textures: dict[str, list[Path]] = {}
    for recording in sorted(path for path in bags.iterdir() if path.is_dir()):
        textures.setdefault(recording.name.rsplit('_', 1)[0], []).append(recording)
    short = {name: len(found) for name, found in textures.items() if len(found) < per_texture}
    if short:
        raise SystemExit(f'error: --recordings {per_texture}: {bags} has fewer for {short}')
    partial = work / f'.{subset.name}.partial'
    shutil.rmtree(partial, ignore_errors=True)
    for found in textures.values():
        for recording in found[:per_texture]:
            shutil.copytree(recording, partial / recording.name, copy_function=os.link)
    partial.rename(subset)
    return subset


def _git(*arguments: str) -> str:
    """A git command's output in this checkout (failing loudly)."""
    return subprocess.run(['git', *arguments], cwd=Path(__file__).parent, check=True,
                          capture_output=True, text=True).stdout.strip()


def resolve_commit(code: str | None) -> str | None:
    """The full hash of --code; else this checkout's HEAD (`-dirty`: src/ changed) or None."""
    try:
        if code is not None:
            return _git('rev-parse', '--verify', '--quiet', f'{code}^{{commit}}')
        dirty = _git('status', '--porcelain', '--untracked-files=no', '--', '../src')
        return _git('rev-parse', 'HEAD') + ('-dirty' if dirty else '')
    except OSError:
        if code is None:  # no git: the recipe names no commit
            return None
        raise SystemExit(f'error: --code {code}: git is not installed here; install it, or '
                         'leave --code out') from None
    except subprocess.CalledProcessError:
        if code is None:  # not a git checkout
            return None
        raise SystemExit(f'error: --code {code}: not a commit of this clone; give a commit '
                         'it holds (git log), or leave --code out') from None


@contextlib.contextmanager
def worktree_env(commit: str, work: Path) -> Iterator[dict]:
    """The environment that runs tactex as it was at `commit` (a worktree, removed after).

    A worktree left by a killed run is removed first.
    """
    tree = (work / f'code-{commit[:12]}').resolve()
    try:
        if tree.exists():
            subprocess.run(['git', 'worktree', 'remove', '--force', str(tree)],
                           cwd=Path(__file__).parent, capture_output=True, check=False)
            shutil.rmtree(tree, ignore_errors=True)
            _git('worktree', 'prune')
        _git('worktree', 'add', '--detach', '--force', str(tree), commit)
    except subprocess.CalledProcessError as failed:
        reason = (failed.stderr.strip().splitlines() or ['(no message)'])[-1]
        raise SystemExit(f'error: --code {commit[:12]}: git cannot check it out into {tree} '
                         f'({reason}); remove that folder, or give another --work') from None
    try:
        sources = [str(package) for package in sorted((tree / 'src').iterdir())
                   if package.is_dir()]
        yield {**os.environ, 'PYTHONPATH': os.pathsep.join(
            [*sources, *filter(None, [os.environ.get('PYTHONPATH')])])}
    finally:
        _git('worktree', 'remove', '--force', str(tree))


def check_kept_data(results: Path, paths: dict[int, Path]) -> None:
    """Refuse datasets other than those the kept grid in `results` was started with."""
    from tactex_classify.evaluation.model_grid import GridError, GridStore
    if not (results / 'grid.json').is_file():
        print(f'{results} holds no grid yet: nothing to check the datasets against')
        return
    try:
        GridStore(results).check_data({window: Dataset.load(path)
                                       for window, path in paths.items()})
    except GridError as err:
        message = str(err).replace('or a new --out', 'or a new --grid')
        raise SystemExit(f'error: {message}; its data_recipe in run.json says how they were '
                         'built') from None


def _kept_run(results: Path) -> dict:
    """A grid's run.json: its datasets' digests, its data recipe and its calls."""
    path = results / 'run.json'
    return (json.loads(path.read_text(encoding='utf-8')) if path.is_file()
            else {'datasets': {}, 'calls': []})


def _write_run(results: Path, record: dict) -> None:
    """Write a grid's run.json."""
    results.mkdir(parents=True, exist_ok=True)
    (results / 'run.json').write_text(json.dumps(record, indent=2) + '\n', encoding='utf-8')


def machine() -> dict:
    """What ran the grid: cores and, where torch sees one, the GPU (its name and memory)."""
    import torch
    found = {'cpu_count': os.cpu_count(), 'gpu': None}
    if torch.cuda.is_available():
        properties = torch.cuda.get_device_properties(0)
        found['gpu'] = {'name': properties.name,
                        'memory_gib': round(properties.total_memory / 2**30, 1),
                        'torch': torch.__version__}
    return found


def main() -> int:
    """Build the data if needed, run (or resume) the grid, note what was done."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--work', type=Path, default=Path('/tmp/tactex-compare-data'),
                        help='where the bags and the converted datasets are kept')
    parser.add_argument('--bags', type=Path, help='use these bags instead of collecting')
    parser.add_argument('--epochs', type=int, default=1)
    parser.add_argument('--folds', type=int, default=5)
    parser.add_argument('--seeds', type=int, default=1)
    parser.add_argument('--recordings', type=int,
                        help='keep the first N recordings of each texture (default: all)')
    parser.add_argument('--cpus', type=int, default=2)
    parser.add_argument('--models', help='comma-separated (default: every model)')
    parser.add_argument('--cv', default='both', choices=('grouped', 'stratified', 'both'))
    parser.add_argument('--early-stopping', type=int, default=0,
                        help='patience in epochs on held-out recordings (0: off)')
    parser.add_argument('--grid', default='compare',
                        help='folder under bench/results/ (default compare; compare_converged '
                             'is the main comparison)')
    parser.add_argument('--profile', default='original', choices=('original', 'modern'))
    parser.add_argument('--scaling', default='minmax', choices=('minmax', 'standard', 'window'))
    parser.add_argument('--device', default='cpu', choices=('auto', 'cpu', 'cuda'),
                        help="the deep models' device (tactex compare --device)")
    parser.add_argument('--cells-per-gpu', type=int, default=1)
    parser.add_argument('--mps', action='store_true',
                        help="share each GPU through NVIDIA's MPS (tactex compare --mps)")
    parser.add_argument('--sweeps', type=int, default=25,
                        help='sweeps per texture to collect when there are no bags (default 25)')
    parser.add_argument('--code', metavar='COMMIT',
                        help='collect and convert with the tactex of this commit (a git '
                             "worktree): rebuilds a kept grid's data after the simulator changed")
    parser.add_argument('--data-only', action='store_true',
                        help="build the datasets into --work, check them against the grid's "
                             'digests, note their recipe in run.json and stop')
    parser.add_argument('--windows', default=','.join(map(str, WINDOWS)),
                        help='comma-separated window sizes (default 128,256,512); a later call '
                             'with more windows adds them to the same grid')
    args = parser.parse_args()
    started = time.strftime('%Y-%m-%dT%H:%M:%S%z')
    results = RESULTS / args.grid
    steps: list[dict] = []
    suffix = f'_first{args.recordings}' if args.recordings else ''
    windows = dict.fromkeys(int(w) for w in args.windows.split(','))  # in order, once each
    paths = {window: args.work / f'sim{window}{suffix}.npz' for window in windows}
    missing = {window: data for window, data in paths.items() if not data.is_file()}
    recipe = None
    if missing:  # datasets converted before (or carried to a lent GPU) need no bags
        commit = resolve_commit(args.code)
        source = args.bags or args.work / (f'bags-{commit[:12]}-{args.sweeps}' if args.code
                                           else 'bags')
        collected = not source.is_dir()
        if collected and args.sweeps < max(1, args.recordings or 0):
            parser.error(f'--sweeps {args.sweeps}: collect at least one sweep per texture, '
                         'and at least --recordings')
        args.work.mkdir(parents=True, exist_ok=True)
        try:
            with (worktree_env(commit, args.work) if args.code
                  else contextlib.nullcontext()) as env:
                if collected:  # into a partial folder, renamed once every sweep is in
                    partial = args.work / f'.{source.name}.partial'
                    shutil.rmtree(partial, ignore_errors=True)
                    _timed([TACTEX, 'sim', 'collect', '--scene', 'uneven_texture', '--sweeps',
                            str(args.sweeps), '--workers', str(args.cpus), '--out',
                            str(partial)], steps, env)
                    partial.rename(source)
                bags = (first_recordings(source, args.recordings, args.work)
                        if args.recordings else source)
                for window, data in missing.items():
                    _timed([TACTEX, 'convert', str(bags), '--out', str(data), '--window',
                            str(window)], steps, env)
        except (KeyboardInterrupt, subprocess.CalledProcessError) as stopped:
            what = ('interrupted' if isinstance(stopped, KeyboardInterrupt)
                    else f'{stopped.cmd[1]} {stopped.cmd[2]} ended with exit '
                         f'{stopped.returncode}')
            raise SystemExit(f'error: building the datasets in {args.work}: {what}; run '
                             'again (whole bags and datasets are kept)') from None
        recipe = {'code': commit, 'scene': 'uneven_texture',
                  'sweeps': args.sweeps if collected else None,
                  'recordings_per_texture': args.recordings, 'windows': list(windows),
                  'bags': None if collected else str(source), 'steps': list(steps)}
    check_kept_data(results, paths)
    datasets = list(paths.values())
    if args.data_only:
        if recipe:
            _write_run(results, {**_kept_run(results), 'data_recipe': recipe})
        print(f'datasets in {args.work}: ' + ', '.join(data.name for data in datasets))
        return 0
    command = [TACTEX, 'compare', *map(str, datasets), '--epochs', str(args.epochs),
               '--folds', str(args.folds), '--seeds', str(args.seeds), '--cpus', str(args.cpus),
               '--cv', args.cv, '--early-stopping', str(args.early_stopping),
               '--profile', args.profile, '--scaling', args.scaling, '--device', args.device,
               '--cells-per-gpu', str(args.cells_per_gpu), '--out', str(results)]
    if args.models:
        command += ['--models', args.models]
    if args.mps:
        command.append('--mps')
    try:
        _timed(command, steps)
    except KeyboardInterrupt:
        print('interrupted: the finished cells and the report are kept; run again to resume',
              file=sys.stderr)
        return 130
    except subprocess.CalledProcessError as failed:
        print(f'error: {Path(failed.cmd[0]).name} {failed.cmd[1]} ended with exit '
              f'{failed.returncode}; the finished cells and the report are kept; run again '
              'to resume', file=sys.stderr)
        return 1
    finally:
        record = _kept_run(results)
        for data in datasets:  # of the arrays, as in grid.json: a carried copy may be stored
            record['datasets'][data.name] = Dataset.load(data).digest()
        if recipe:
            record['data_recipe'] = recipe
        record['calls'].append({'started': started,
                                'cpus': args.cpus, 'recordings_per_texture': args.recordings,
                                'machine': machine(), 'steps': steps})
        _write_run(results, record)
    return 0


if __name__ == '__main__':
    sys.exit(main())
