# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Write the docs site's benchmark figures from the outputs kept in bench/results/.

Every benchmark figure of the docs (docs/*/*.md) sits in a generated section between
`<!-- results:NAME -->` and `<!-- /results -->`, each section on exactly one page; this
script renders each from the files the benchmarks left in bench/results/ and rewrites only
what lies between the markers, so prose and figures cannot disagree with the kept outputs.
`make results` runs it; `--check` exits 1 (listing the stale sections) instead of writing,
which the test suite uses. Figures are linked through docs/results, a link to bench/results.
The sections themselves are written by results_system, results_learning,
results_recordings and results_identification (what they share: results_common).
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
import re
import sys
import textwrap

sys.path.insert(0, str(Path(__file__).resolve().parent))  # the result modules beside it
from results_identification import (  # noqa: E402
    identification,
    identification_init,
    identification_power,
    identification_seeds,
    live_sections,
    texture_signal,
)
from results_learning import (  # noqa: E402
    architectures,
    channels,
    compare,
    compare_converged,
    compare_gpu,
    compare_gpu_full,
    compare_long,
    convergence_check,
    gpu_pace,
    init,
    learning_curves,
    profiles,
    sensor_stats,
    sim_to_real,
    synthetic_set,
    textures,
    training,
    window_voting,
)
from results_recordings import convert, predict_play, recordings  # noqa: E402
from results_system import (  # noqa: E402
    driver,
    kinematics,
    madgwick,
    observers,
    online_accuracy,
    online_latency,
    sensor_decoder,
    sensor_node,
    sim,
    sim_collect,
    sweep,
)

DOCS = Path(__file__).parents[1] / 'docs'
SECTION = re.compile(r'(<!-- results:(?P<name>[a-z_]+) -->\n)(?P<body>.*?)(<!-- /results -->)',
                     re.DOTALL)
WIDTH = 90


SECTIONS: dict[str, Callable[[], str]] = {
    'sensor_decoder': sensor_decoder, 'sensor_node': sensor_node, 'madgwick': madgwick,
    'observers': observers,
    'driver': driver, 'sim': sim, 'convert': convert, 'synthetic_set': synthetic_set,
    'textures': textures, 'init': init, 'kinematics': kinematics, 'sweep': sweep,
    'sim_collect': sim_collect, 'training': training, 'compare': compare,
    'compare_long': compare_long, 'compare_gpu': compare_gpu,
    'compare_gpu_full': compare_gpu_full,
    'gpu_pace': gpu_pace,
    'compare_converged': compare_converged, 'convergence_check': convergence_check,
    'online_accuracy': online_accuracy, 'online_latency': online_latency,
    'sensor_stats': sensor_stats, 'channels': channels, 'profiles': profiles,
    'architectures': architectures, 'window_voting': window_voting,
    'sim_to_real': sim_to_real, 'learning_curves': learning_curves,
    'recordings': recordings, 'predict_play': predict_play, 'identification': identification,
    **live_sections(),
    'texture_signal': texture_signal,
    'identification_init': identification_init,
    'identification_seeds': identification_seeds,
    'identification_power': identification_power}


def _wrapped(text: str) -> str:
    """Paragraphs wrapped at the docs' width (tables as they are, bullets indented)."""
    paragraphs = text.strip('\n').split('\n\n')
    return '\n\n'.join(part if part.startswith('|') else textwrap.fill(
        part, WIDTH, subsequent_indent='  ' if part.startswith('- ') else '',
        break_on_hyphens=False, break_long_words=False) for part in paragraphs) + '\n'


def render() -> dict[str, str]:
    """Every generated section, rendered from the kept outputs."""
    return {name: _wrapped(make()) for name, make in SECTIONS.items()}


def pages() -> dict[Path, str]:
    """The docs pages that may hold generated sections (docs/*/*.md), and their text."""
    return {path: path.read_text(encoding='utf-8') for path in sorted(DOCS.glob('*/*.md'))
            if path.parent.name not in ('results', 'reference')}


def placed(texts: dict[Path, str], sections: dict[str, str]) -> dict[str, Path]:
    """The page of each generated section.

    Raises:
        ValueError: a marker names no known section, a known one has no marker, or one
            has more than one.
    """
    found = [(match['name'], path) for path, text in texts.items()
             for match in SECTION.finditer(text)]
    names = [name for name, _ in found]
    unknown = sorted(set(names) - set(sections))
    missing = sorted(set(sections) - set(names))
    twice = sorted({name for name in names if names.count(name) > 1})
    if unknown or missing or twice:
        raise ValueError(f'docs markers: unknown {unknown}, missing {missing}, twice {twice}')
    return {name: path for name, path in found}


def rewrite(text: str, sections: dict[str, str]) -> str:
    """`text` with every generated section replaced by its rendering.

    Raises:
        ValueError: a marker names no known section.
    """
    unknown = sorted({match['name'] for match in SECTION.finditer(text)} - set(sections))
    if unknown:
        raise ValueError(f'docs markers: unknown {unknown}')
    return SECTION.sub(lambda m: m.group(1) + sections[m['name']] + m.group(4), text)


def stale(text: str, sections: dict[str, str]) -> list[str]:
    """Names of the sections whose text differs from their rendering."""
    return [m['name'] for m in SECTION.finditer(text) if m['body'] != sections[m['name']]]


def main(argv: list[str] | None = None) -> int:
    """Rewrite the docs pages' generated sections (or, with --check, only compare)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--check', action='store_true', help='compare only; exit 1 if stale')
    args = parser.parse_args(argv)
    texts = pages()
    sections = render()
    placed(texts, sections)
    if args.check:
        names = [name for text in texts.values() for name in stale(text, sections)]
        if names:
            print(f'error: docs sections out of date: {", ".join(names)}; run make results',
                  file=sys.stderr)
            return 1
        return 0
    for path, text in texts.items():
        if (new := rewrite(text, sections)) != text:
            path.write_text(new, encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
