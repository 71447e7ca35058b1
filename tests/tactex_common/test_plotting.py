# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The house style of every figure tactex writes: one panel size, legends off the data.

A figure is a grid of panels of 5.5 x 4.0 inches at 110 dpi (605 x 440 pixels); a
confusion matrix's panel of n classes is max(4.0, 2.0 + 0.35 n) inches high and 1.5
inches wider than high. Every legend lies outside every panel's data area and inside the
figure. Each plotting function of the workspace is called here on tiny inputs.
"""

from pathlib import Path
import warnings

from matplotlib.figure import Figure
import numpy as np
from PIL import Image
import pytest

from tactex.accuracy_time import plots
from tactex.demo import figures as demo
from tactex.soak.bookkeeping import FaultRecord, plot_memory
from tactex_classify.data.bags import Recording
from tactex_classify.data.signal_stats import plot_spectra, TextureSignals
from tactex_classify.evaluation import grid_report, prediction_report, training_report
from tactex_classify.evaluation.recording_plot import plot_recording
from tactex_classify.online.replay import Replayed
from tactex_common import plotting
from tactex_common.channels import CHANNELS
from tactex_sim.scene import load_scene, resolve_scene

PANEL_PX = (605, 440)
DPI = 110


def confusion_panel_px(classes: int) -> tuple[float, float]:
    height = max(4.0, 2.0 + 0.35 * classes)
    return DPI * (height + 1.5), DPI * height


# Every (width, height) a figure may have: up to 4 x 4 panels of one of the panel sizes.
PANELS = [PANEL_PX] + [confusion_panel_px(n) for n in range(1, 41)]
ALLOWED_PX = [(columns * width, rows * height) for width, height in PANELS
              for rows in range(1, 5) for columns in range(1, 5)]


def allowed(size: tuple[int, int]) -> bool:
    """Whether `size` (pixels) is a grid of house panels, to the rounding of a pixel."""
    return any(abs(size[0] - w) <= 1 and abs(size[1] - h) <= 1 for w, h in ALLOWED_PX)


def test_the_module_states_the_same_house_style():
    assert (plotting.DPI * plotting.PANEL_IN[0], plotting.DPI * plotting.PANEL_IN[1]) \
        == PANEL_PX
    for classes in (2, 5, 6, 13, 30):
        width, height = plotting.panel_in(classes)
        assert (DPI * width, DPI * height) == pytest.approx(confusion_panel_px(classes))


@pytest.fixture
def written(monkeypatch):
    """Every figure saved while the test runs: its file, size and where its legends sit."""
    seen = []
    original = Figure.savefig

    def savefig(figure, path, *args, **kwargs):
        original(figure, path, *args, **kwargs)
        figure.canvas.draw()
        renderer = figure.canvas.get_renderer()
        panels = [axes.get_window_extent(renderer) for axes in figure.axes
                  if axes.get_visible()]
        legends = [axes.get_legend() for axes in figure.axes] + list(figure.legends)
        boxes = [legend.get_window_extent(renderer) for legend in legends
                 if legend is not None and legend.get_visible()]
        seen.append({'path': Path(path), 'panels': panels, 'legends': boxes,
                     'figure': figure.bbox})
    monkeypatch.setattr(Figure, 'savefig', savefig)
    return seen


SURFACE = load_scene(resolve_scene('uneven_texture')).surface


def draw_demo(folder: Path) -> None:
    xs = np.array([0.10, 0.13, 0.17])
    positions = np.array([[x, 0.0, float(SURFACE.height(x))] for x in xs])
    normals = np.tile([0.0, 0.0, 1.0], (3, 1))
    demo.plot_pathway(folder / 'pathway.png', positions, normals, SURFACE)
    sweeps = [(f'texture {k}', [(0.1 * i, i / 20, 5 <= i <= 15 + k, 0.015) for i in range(21)])
              for k in range(3)]
    demo.plot_sweeps(folder / 'sweep.png', sweeps, demo.path_length(positions), 0.015)
    matrix = np.arange(12 * 13).reshape(12, 13) % 3
    demo.plot_confusion(folder / 'confusion.png', matrix, [f'texture {k}' for k in range(12)])
    demo.plot_accuracy_against_time(folder / 'accuracy.png', np.array([0.5, 1.0, 2.0]),
                                    np.array([0.3, 0.6, 0.9]), 1 / 12)


def draw_accuracy_time(folder: Path) -> None:
    points = [{'model': model, 'window': 64, 'threshold': threshold, 'contact_s': s,
               'accuracy': accuracy, 'pareto': model == 'cnn_1'}
              for model in ('cnn_1', 'extratrees') for threshold in (None, 0.9)
              for s, accuracy in ((0.5, 0.4), (2.0, 0.7), (8.0, 0.9))]
    plots.contact_time(folder / 'contact.png', points, 'test data')
    rows = [{'model': model, 'accuracy': 0.8, 'train_s': 10.0 * (index + 1), 'deep': index == 0,
             'latency': {'torch': {'single_s': 0.001}, 'onnxruntime': {'single_s': 0.0005}}}
            for index, model in enumerate(('cnn_1', 'extratrees'))]
    plots.compute_time(folder / 'compute.png', rows, 'test data')
    plots.probing(folder / 'probing.png', [{'normal_mean_deg': 1.0, 'position_mean_mm': 0.5,
                                            'probing_s': 30.0, 'step_mm': 5.0,
                                            'descent_mm_s': 2.0}], 'test data')
    plots.sweep_speed(folder / 'speed.png', [
        {'speed_mm_s': speed, 'contact_fraction': 0.9, 'contact_fraction_min': 0.8,
         'window_accuracy': 0.6, 'sweep_accuracy': 0.7, 'failed': ''} for speed in (10, 20)],
        'test data')
    plots.simulation_cost(folder / 'simulation.png', [
        {'real_time_factor': 1.0 + k, 'distance_db': 2.0 * k, 'variant': f'variant {k}'}
        for k in range(3)], 'test data')
    plots.filter_rate(folder / 'filter.png', [
        {'rate_hz': rate, 'gain': gain, 'rms_attitude_deg': 1.0 / gain}
        for rate in (120.0, 400.0) for gain in (0.01, 0.1)],
        [{'rate_hz': rate, 'stream_us': 5.0, 'batch_us': 0.5} for rate in (120.0, 400.0)],
        'test data')
    plots.whole_job(folder / 'whole_job.png', [
        {'stage': stage, 'wall_s': 10.0, 'arm_s': 5.0} for stage in ('probe', 'sweep', 'train')],
        'test data')


def draw_soak(folder: Path) -> None:
    faults = [FaultRecord(30, 'sensor_unplug', True), FaultRecord(60, 'node_kill', False)]
    plot_memory(folder / 'memory.png', {'sweep_node': [(0, 1e8), (60, 1.1e8)],
                                        'classifier_node': [(0, 2e8), (60, 2e8)]}, faults)


def draw_training(folder: Path) -> None:
    history = [{'epoch': e, 'train_loss': 1 / e, 'train_accuracy': 0.5, 'val_accuracy': 0.4}
               for e in (1, 2, 3)]
    scheme = {'confusion': [[3, 1, 0], [0, 4, 0], [1, 0, 3]], 'accuracy': 10 / 12,
              'histories': [history, history], 'sequence': [
                  {'touch_s': s, 'accuracy': 0.5 + 0.1 * s} for s in (0.5, 1.0, 2.0)]}
    training_report.plot_run(folder, ['a', 'b', 'c'], {'grouped': scheme, 'stratified': scheme})


def draw_grid(folder: Path) -> None:
    def row(model: str, accuracy: float, cost: float) -> dict:
        figure = {'accuracy': {'mean': accuracy, 'sd': 0.05}, 'train_s': {'mean': cost},
                  'latency_ms': {'mean': cost / 10}}
        return {'window': 64, 'model': model, 'schemes': {'grouped': figure,
                                                          'stratified': figure}}
    grid_report.plot_grid(folder, [row('cnn_1', 0.6, 1.0), row('extratrees', 0.8, 5.0)])


def draw_prediction(folder: Path) -> None:
    results = [Replayed(name=f'rec{k}', label=label, start_ns=0,
                        decisions=[(10**9, 'a')] if k else [])
               for k, label in enumerate(('a', 'b', 'a'))]
    prediction_report.write_report(folder, results, ['a', 'b'], {})


def draw_recording(folder: Path) -> None:
    count = 240
    stamps = 10**12 + np.arange(count, dtype=np.int64) * 8_333_333
    values = np.random.default_rng(0).normal(size=(count, len(CHANNELS)))
    recording = Recording(path=folder / 'wood_1', stamps_ns=stamps, values=values,
                          metadata={'label': 'wood'}, active_ns=None,
                          joint_stamps_ns=np.zeros(0, dtype=np.int64), joint_speed=np.zeros(0))
    plot_recording(folder / 'recording.png', recording, np.arange(count) > 60)


def draw_spectra(folder: Path) -> None:
    rng = np.random.default_rng(1)
    textures = {name: TextureSignals(rate_hz=120.0, recordings=1, samples={
        channel: [rng.normal(size=600)] for channel in CHANNELS}) for name in ('wood', 'felt')}
    assert len(plot_spectra(textures, folder)) == 4


@pytest.mark.parametrize('draw', [draw_demo, draw_accuracy_time, draw_soak, draw_training,
                                  draw_grid, draw_prediction, draw_recording, draw_spectra],
                         ids=lambda draw: draw.__name__.removeprefix('draw_'))
def test_every_figure_is_a_grid_of_house_panels_with_its_legends_off_the_data(
        draw, written, tmp_path):
    draw(tmp_path)
    assert written
    for saved in written:
        name = saved['path'].name
        with Image.open(saved['path']) as image:
            assert allowed(image.size), f'{name} is {image.size} pixels'
        for legend in saved['legends']:
            assert saved['figure'].contains(legend.x0, legend.y0) \
                and saved['figure'].contains(legend.x1, legend.y1), f'{name}: legend cut off'
            hidden = [panel for panel in saved['panels'] if legend.overlaps(panel)]
            assert not hidden, f'{name}: a legend lies on the data of a panel'
    legends = sum(len(saved['legends']) for saved in written)
    assert legends or draw is draw_prediction  # every other draw has at least one legend


def test_a_legend_of_many_entries_takes_columns_rather_than_run_off_the_figure(written,
                                                                              tmp_path):
    plt, figure, axes = plotting.figure()
    for k in range(40):
        axes.plot([0, 1], [k, k + 1], label=f'texture {k}')
    plotting.legend_outside(axes)
    plotting.save(plt, figure, tmp_path / 'many.png')
    (saved,) = written
    legend = saved['legends'][0]
    assert saved['figure'].contains(legend.x0, legend.y0)
    assert saved['figure'].contains(legend.x1, legend.y1)


def label_boxes(xs, ys, names):
    """The display boxes of `names` labelling (xs, ys) on a house panel, after label_points."""
    plt, figure, axes = plotting.figure()
    axes.scatter(xs, ys)
    axes.set_xscale('log')
    plotting.label_points(axes, xs, ys, names)
    renderer = figure.canvas.get_renderer()
    boxes = [text.get_window_extent(renderer) for text in axes.texts]
    plt.close(figure)
    return boxes


def test_point_labels_that_would_lie_on_each_other_are_moved_apart_the_same_way_each_time():
    # The main comparison's cost against accuracy: rows within a point of accuracy and a
    # few seconds of cost, whose labels written at their points would cover each other.
    rows = {'extratrees 128': (1.6, 27.3), 'minirocket 128': (12.0, 35.8),
            'hydra 128': (17.0, 20.6), 'multirocket 128': (58.0, 41.9),
            'multirocket_hydra 128': (72.0, 41.3), 'cnn_attention 128': (72.0, 42.7),
            'self_attention 128': (121.0, 46.1), 'cnn_3 128': (121.0, 62.7),
            'cnn_1 128 (not converged)': (102.0, 62.0), 'resnet 128': (337.0, 65.8),
            'inception_time 128': (715.0, 71.0)}
    names = list(rows)
    xs, ys = zip(*rows.values(), strict=True)
    boxes = label_boxes(xs, ys, names)
    assert len(boxes) == len(names)
    for i, box in enumerate(boxes):
        for other in boxes[i + 1:]:
            assert not box.overlaps(other), 'two point labels lie on each other'
    again = label_boxes(xs, ys, names)
    assert [tuple(box.bounds) for box in again] == [tuple(box.bounds) for box in boxes]


def test_a_point_that_is_not_drawn_gets_no_label():
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        boxes = label_boxes([1.0, 2.0, 3.0, 4.0], [float('nan'), 3.0, float('inf'), 5.0],
                            ['lost', 'kept', 'off the chart', 'also kept'])
    assert len(boxes) == 2


def test_a_log_axis_under_a_decade_is_labelled_in_plain_numbers():
    # The GPU grid's latencies (2 to 30 ms) once read "2 x 10^0 3 x 10^0 4 x 10^0 ..."
    plt, figure, axes = plotting.figure()
    axes.scatter([2.0, 9.7, 19.0, 30.0], [35, 19, 42, 27])
    axes.set_xscale('log')
    plotting.plain_log_ticks(axes.xaxis)
    figure.canvas.draw()
    low, high = axes.get_xlim()
    shown = [label.get_text() for label, at in zip(axes.get_xticklabels(), axes.get_xticks(),
                                                  strict=True) if low <= at <= high]
    minor = [label.get_text() for label in axes.get_xticklabels(minor=True)]
    plt.close(figure)
    assert shown == ['2', '5', '10', '20'] and not any(minor)


def test_a_label_no_installed_font_can_draw_writes_the_figure_without_a_warning(tmp_path):
    import warnings

    from tactex_common import plotting
    plt, made, axes = plotting.figure()
    axes.set_title('ü 木 x')  # a class name of the user's, in a script DejaVu lacks
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        plotting.save(plt, made, tmp_path / 'f.png')
    assert (tmp_path / 'f.png').read_bytes()[:4] == b'\x89PNG'
