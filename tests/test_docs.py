# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The docs site builds without a broken link, its reference is current, its names exist.

The site (mkdocs.yml, docs/) is the project's documentation and README.md its entry
point. What they name must be real: every `tactex ...` command line names existing
commands and subcommands and only options those take; every standalone `--option` is an
option of a tactex command or of a script in bench/ or tools/; every node parameter they
name (a code span followed by "parameter" or by "in config/...") is declared by a node or
set in config/*.yaml. The reference pages are what tools/write_reference_docs.py writes
from the code today, and the README keeps the test command that CI runs.
"""

import argparse
from pathlib import Path
import re
import subprocess
import sys

import pytest
from support.scripts import load_script
import yaml

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / 'docs'
README = ROOT / 'README.md'
MKDOCS_GUARD_S = 240  # a hang guard, not a timing claim
# Options of programs other than tactex and the repository's scripts that the pages show.
FOREIGN_OPTIONS = {
    '--hypothesis-seed': 'pytest (hypothesis plugin)',
    '--hypothesis-profile': 'pytest (hypothesis plugin)',
    '--strict': 'mkdocs build',
    '--symlink-install': 'colcon build',
    '--params-file': 'a node (ros2 run ... --ros-args)',
    '--print-description': 'ros2 launch',
}


def _written_pages() -> dict[str, str]:
    """README.md and every hand-written docs page (not the generated reference or results)."""
    pages = {'README.md': README.read_text(encoding='utf-8')}
    for path in sorted(DOCS.rglob('*.md')):
        if path.relative_to(DOCS).parts[0] not in ('reference', 'results'):
            pages[str(path.relative_to(ROOT))] = path.read_text(encoding='utf-8')
    return pages


def code_spans(text: str) -> list[str]:
    """Inline code spans (whitespace collapsed) and the lines of fenced code blocks."""
    spans, prose, fenced = [], [], False
    for line in text.splitlines():
        if line.lstrip().startswith('```'):
            fenced = not fenced
        elif fenced:
            spans.append(line.split(' #')[0].strip())
        else:
            prose.append(line)
    spans += [' '.join(span.split()) for span in re.findall(r'`([^`]+)`', '\n'.join(prose))]
    return spans


def tactex_command_lines(span: str) -> list[list[str]]:
    """The words after `tactex` of each tactex command line in a code span."""
    lines = []
    for part in re.split(r'\s(?:&&|\|\||\||;)\s', span):
        if match := re.search(r'(?:^|[\s/])tactex\s+(.*)$', part):
            lines.append(match[1].split())
    return lines


def _parsers() -> dict[str, argparse.ArgumentParser]:
    return load_script('tools/write_reference_docs.py').commands()


def _subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    return load_script('tools/write_reference_docs.py')._subcommands(parser)


def command_problems(words: list[str], root: argparse.ArgumentParser) -> list[str]:
    """What is wrong with `tactex WORDS`: an unknown command or an option it does not take."""
    parser, path = root, 'tactex'
    while (choices := _subcommands(parser)) and words and not words[0].startswith('-'):
        name = words[0]
        if name.isupper() or not re.fullmatch(r'[a-z][a-z0-9-]*', name):
            return []  # a placeholder (COMMAND) or prose, not a command name
        if name not in choices:
            return [f'{path} has no command {name!r}']
        parser, path, words = choices[name], f'{path} {name}', words[1:]
    options = {option for action in parser._actions for option in action.option_strings}
    return [f'{path} has no option {option[1]}'
            for option in (re.match(r'\[?(--[a-z][a-z0-9-]*)', word) for word in words)
            if option and option[1] not in options]


def _script_options() -> set[str]:
    return {option for folder in ('bench', 'tools') for path in (ROOT / folder).glob('*.py')
            for option in re.findall(r"'(--[a-z][a-z0-9-]*)'", path.read_text(encoding='utf-8'))}


def mentioned_parameters(text: str) -> set[str]:
    """Names the text calls a node parameter.

    A code span followed by "parameter(s)" or by "in/of config/NAME.yaml", or a `-p NAME:=`
    override.
    """
    name = r'([a-z_][a-z0-9_.]*)'
    return set(re.findall(rf"`{name}`'?s? parameters?\b", text)
               + re.findall(rf'`{name}`\s+(?:in|of)\s+`?config/\w+\.yaml', text)
               + re.findall(rf'-p\s+{name}:=', text))


def _yaml_keys(node, prefix: str = '') -> set[str]:
    keys = set()
    if isinstance(node, dict):
        for key, value in node.items():
            keys |= {str(key), f'{prefix}{key}'} | _yaml_keys(value, f'{prefix}{key}.')
    return keys


def known_parameters() -> set[str]:
    """Every parameter a node declares (the generated reference) or config/*.yaml sets."""
    reference = (DOCS / 'reference' / 'parameters.md').read_text(encoding='utf-8')
    names = set(re.findall(r'^\| `([^`]+)` \|', reference, re.MULTILINE))
    for path in (ROOT / 'config').glob('*.yaml'):  # parameter files; movements.yaml is not
        for node in yaml.safe_load(path.read_text(encoding='utf-8')).values():
            if isinstance(node, dict):
                names |= _yaml_keys(node.get('ros__parameters', {}))
    return names


@pytest.mark.integration
def test_the_site_builds_with_strict_checks_so_no_link_is_broken(tmp_path):
    result = subprocess.run(
        [sys.executable, '-m', 'mkdocs', 'build', '--strict', '--config-file',
         str(ROOT / 'mkdocs.yml'), '--site-dir', str(tmp_path / 'site')],
        capture_output=True, text=True, timeout=MKDOCS_GUARD_S,
        env={'NO_MKDOCS_2_WARNING': '1', 'PATH': str(Path(sys.executable).parent)})
    assert result.returncode == 0, result.stdout + result.stderr
    assert (tmp_path / 'site' / 'reference' / 'cli' / 'index.html').is_file()


@pytest.mark.integration
@pytest.mark.ros
def test_the_reference_pages_are_what_the_generator_writes_from_the_code_today(tmp_path):
    subprocess.run([sys.executable, str(ROOT / 'tools' / 'write_reference_docs.py'),
                    '--out', str(tmp_path)], check=True, capture_output=True,
                   timeout=MKDOCS_GUARD_S)
    written = sorted(path.name for path in tmp_path.iterdir())
    assert written == sorted(path.name for path in (DOCS / 'reference').glob('*.md'))
    stale = [name for name in written if (tmp_path / name).read_text(encoding='utf-8')
             != (DOCS / 'reference' / name).read_text(encoding='utf-8')]
    assert not stale, f'run .venv/bin/python tools/write_reference_docs.py: {stale} stale'


def test_the_cli_reference_has_every_command_and_subcommand():
    page = (DOCS / 'reference' / 'cli.md').read_text(encoding='utf-8')
    assert [path for path in _parsers() if f'## `{path}`' not in page] == []


def test_every_tactex_command_and_option_the_docs_name_exists():
    root = _parsers()['tactex']
    problems = [f'{page}: `tactex {" ".join(words)}`: {problem}'
                for page, text in _written_pages().items() for span in code_spans(text)
                for words in tactex_command_lines(span)
                for problem in command_problems(words, root)]
    assert problems == []


def test_every_standalone_option_the_docs_name_belongs_to_a_command_or_script():
    options = {option for parser in _parsers().values() for action in parser._actions
               for option in action.option_strings} | _script_options() | set(FOREIGN_OPTIONS)
    unknown = sorted({f'{page}: {match[1]}' for page, text in _written_pages().items()
                      for span in code_spans(text)
                      if (match := re.match(r'(--[a-z][a-z0-9-]*)', span))
                      and match[1] not in options})
    assert unknown == []


def test_every_node_parameter_the_docs_name_is_declared_or_configured():
    known = known_parameters()
    unknown = sorted({f'{page}: {name}' for page, text in _written_pages().items()
                      for name in mentioned_parameters(text) if name not in known})
    assert unknown == []


def test_the_checks_catch_a_made_up_command_option_or_parameter():
    root = _parsers()['tactex']
    assert command_problems(['sim', 'collect', '--workers', '2'], root) == []
    assert command_problems(['sim', 'gather'], root) == ["tactex sim has no command 'gather'"]
    assert command_problems(['train', '--epoch', '3'], root) == [
        'tactex train has no option --epoch']
    assert tactex_command_lines('make x && .venv/bin/tactex demo --quick') == [
        ['demo', '--quick']]
    assert mentioned_parameters("the bridge's `fault` parameter; `descent_speed` in\n"
                                'config/sweep.yaml; `-p gain:=0.1`'
                                ) == {'fault', 'descent_speed', 'gain'}
    assert 'descent_speedd' not in known_parameters() and 'fault' in known_parameters()


def test_the_readme_is_the_entry_point_with_the_test_command_ci_runs():
    readme = README.read_text(encoding='utf-8')
    assert len(readme.splitlines()) <= 250
    assert ('make test   # set up .venv/ and run the whole test suite (CI runs exactly this)'
            in readme)
    assert 'make test' in (ROOT / '.ci' / 'run').read_text(encoding='utf-8')
    assert re.search(r'^test:.*\n\t\$\(BIN\)/python -m pytest',
                     (ROOT / 'Makefile').read_text(encoding='utf-8'), re.MULTILINE)
    assert '](docs/index.md)' in readme
    assert re.search(r'!\[[^\]]+\]\((bench/results/[^)]+\.png)\)', readme)
    picture = re.search(r'!\[[^\]]+\]\(([^)]+)\)', readme)[1]
    assert (ROOT / picture).is_file()
