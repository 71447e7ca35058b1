# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex plot`: a recording drawn to a PNG, and a run's plots drawn again from its numbers."""

from support.bagfactory import ramp, write_bag
from support.toy_windows import toy

from tactex.cli import main


def test_a_recording_is_drawn_to_the_png_given_and_nothing_else(tmp_path, capsys):
    stamps, values = ramp(300)
    write_bag(tmp_path / 'rec', stamps, values, metadata={'label': 'wood', 'trial': 4})
    before = sorted(p.name for p in (tmp_path / 'rec').iterdir())
    assert main(['plot', str(tmp_path / 'rec'), '--out', str(tmp_path / 'rec.png')]) == 0
    assert (tmp_path / 'rec.png').stat().st_size > 10_000
    assert sorted(p.name for p in (tmp_path / 'rec').iterdir()) == before
    assert f'wrote {tmp_path / "rec.png"}' in capsys.readouterr().out



def test_an_existing_png_is_replaced_only_with_force_and_a_new_folder_is_made(tmp_path):
    stamps, values = ramp(300)
    write_bag(tmp_path / 'rec', stamps, values, metadata={'label': 'wood', 'trial': 4})
    kept = tmp_path / 'kept.png'
    kept.write_bytes(b'kept')
    assert main(['plot', str(tmp_path / 'rec'), '--out', str(kept)]) == 1
    assert kept.read_bytes() == b'kept'
    assert main(['plot', str(tmp_path / 'rec'), '--out', str(kept), '--force']) == 0
    assert kept.stat().st_size > 10_000
    assert main(['plot', str(tmp_path / 'rec'), '--out', str(tmp_path / 'new' / 'p.png')]) == 0
    assert (tmp_path / 'new' / 'p.png').stat().st_size > 10_000

def test_a_train_run_gets_its_plots_back_from_metrics_json(tmp_path, capsys):
    data = toy().save(tmp_path / 'toy.npz')
    run = tmp_path / 'run'
    assert main(['train', str(data), '--model', 'extratrees', '--folds', '3', '--no-final',
                 '--out', str(run)]) == 0
    plots = ('confusion.png', 'learning_curves.png', 'accuracy_vs_time.png')
    for name in plots:
        (run / name).unlink()
    capsys.readouterr()
    assert main(['plot', str(run)]) == 0
    assert all((run / name).stat().st_size > 0 for name in plots)
    assert capsys.readouterr().out.count('.png') == 3
