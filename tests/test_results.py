# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The docs' benchmark figures are what bench/render_results.py makes of bench/results/."""

import json
from pathlib import Path
import sys

import pytest
from support.scripts import load_script

ROOT = Path(__file__).resolve().parents[1]


def _renderer():
    return load_script('bench/render_results.py')


def test_every_generated_docs_section_equals_its_rendering_of_the_kept_outputs():
    renderer = _renderer()
    pages = renderer.pages()
    sections = renderer.render()
    assert set(renderer.placed(pages, sections)) == set(renderer.SECTIONS)
    for text in pages.values():
        assert renderer.rewrite(text, sections) == text
        assert renderer.stale(text, sections) == []


def test_the_readme_holds_no_generated_section_and_the_check_passes():
    assert '<!-- results:' not in (ROOT / 'README.md').read_text(encoding='utf-8')
    assert _renderer().main(['--check']) == 0


def test_a_changed_figure_a_missing_or_a_repeated_marker_is_caught():
    renderer = _renderer()
    pages = renderer.pages()
    sections = renderer.render()
    page = renderer.placed(pages, sections)['driver']
    text = pages[page]
    assert renderer.stale(text.replace(sections['driver'], 'a full cycle takes 0.1 ms\n'),
                          sections) == ['driver']
    with pytest.raises(ValueError, match=r"missing \['driver'\]"):
        renderer.placed({**pages, page: text.replace('<!-- results:driver -->', '')}, sections)
    with pytest.raises(ValueError, match=r"twice \['driver'\]"):
        renderer.placed({**pages, ROOT / 'docs' / 'x' / 'copy.md': text}, sections)
    with pytest.raises(ValueError, match=r"unknown \['nothing'\]"):
        renderer.rewrite('<!-- results:nothing -->\n<!-- /results -->', sections)


def test_a_comparison_missing_cells_is_rendered_as_incomplete(tmp_path, monkeypatch):
    renderer = _renderer()
    kept = sys.modules['results_common']  # where every section reads the kept outputs
    (tmp_path / 'compare').mkdir()
    summary = json.loads((kept.RESULTS / 'compare' / 'summary.json').read_text())
    (tmp_path / 'compare' / 'run.json').write_bytes(
        (kept.RESULTS / 'compare' / 'run.json').read_bytes())
    dropped = summary['rows'].pop()
    halved = summary['rows'][0]
    del halved['schemes']['stratified']
    (tmp_path / 'compare' / 'summary.json').write_text(json.dumps(summary))
    monkeypatch.setattr(kept, 'RESULTS', tmp_path)
    text = renderer.compare()
    assert '**Incomplete**' in text and 'Complete:' not in text
    assert f'window {dropped["window"]} lacks {dropped["model"]}' in text
    assert f'{halved["model"]} (' in text


def test_the_main_comparison_names_rows_short_of_cells_or_not_converged(tmp_path, monkeypatch):
    renderer = _renderer()
    kept = sys.modules['results_common']
    grid = tmp_path / 'compare_converged'
    grid.mkdir()
    summary = json.loads((kept.RESULTS / 'compare_converged' / 'summary.json').read_text())
    run = json.loads((kept.RESULTS / 'compare_converged' / 'run.json').read_text())
    short = next(row for row in summary['rows'] if row['model'] == 'minirocket')
    short['schemes']['grouped']['cells'] -= 1
    falling = next(row for row in summary['rows'] if row['model'] == 'cnn_3')
    falling['not_converged'] = True
    (grid / 'summary.json').write_text(json.dumps(summary))
    (grid / 'run.json').write_text(json.dumps(run))
    monkeypatch.setattr(kept, 'RESULTS', tmp_path)
    text = renderer.compare_converged()
    assert '**Incomplete**: ' in text and 'minirocket (14 of 15)' in text
    assert 'not converged: cnn_3' in text and 'Complete:' not in text
    run['calls'].append({**run['calls'][0], 'machine': {'cpu_count': 16, 'gpu': None}})
    (grid / 'run.json').write_text(json.dumps(run))
    with pytest.raises(ValueError, match='mixes'):
        renderer.compare_converged()


def test_a_grid_projects_its_missing_cells_at_the_pace_its_own_cells_measured(
        tmp_path, monkeypatch):
    _renderer()
    learning = sys.modules['results_learning']
    kept = sys.modules['results_common']
    grid = tmp_path / 'grid'
    (grid / 'cells').mkdir(parents=True)
    # 100 s of wall time; cnn_3 trained 2 cells of 50 s, minirocket 1 cell of 10 s.
    finished = [('cnn_3', 'grouped', 1, 50.0), ('cnn_3', 'stratified', 1, 50.0),
                ('minirocket', 'grouped', 1, 10.0)]
    for number, (model, scheme, fold, seconds) in enumerate(finished):
        (grid / 'cells' / f'{number}.json').write_text(json.dumps({
            'cell': {'model': model, 'window': 128, 'seed': 0, 'fold': fold,
                     'scheme': scheme}, 'train_s': seconds}))
    (grid / 'summary.json').write_text('{}')
    (grid / 'run.json').write_text(json.dumps({'calls': [{'steps': [
        {'command': 'tactex compare data.npz', 'seconds': 100.0}]}]}))
    monkeypatch.setattr(kept, 'RESULTS', tmp_path)
    projection = learning._grid_projection('grid', ['cnn_3', 'resnet', 'minirocket'], [128], 2)
    assert projection['done'] == 3 and projection['wall_min'] == pytest.approx(100 / 60)
    deep, baselines = projection['deep'], projection['baselines']
    assert deep['together'] == pytest.approx(1.0)  # 100 s of training in 100 s
    # cnn_3 lacks one cell per scheme (50 s each); resnet, with none, is taken at the
    # deep cells' mean (50 s) for all four: 300 s at one cell at a time.
    assert deep['left_min'] == pytest.approx(300 / 60)
    # minirocket at 0.1 cells at once: 3 cells of 10 s left take 300 s.
    assert baselines['together'] == pytest.approx(0.1)
    assert baselines['left_min'] == pytest.approx(300 / 60)
    assert projection['left_min'] == pytest.approx(300 / 60)
