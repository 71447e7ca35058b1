# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Result sections of the system: sensor, filter, driver, simulation, motion, latency."""

import numpy as np
from results_common import kept_json, kept_text, line_starting, numbers_in


def sensor_decoder() -> str:
    text = kept_text('bench_sensor_decoder.txt')
    bare, clean, garbage = (numbers_in(line_starting(text, key)) for key in
                            ('bare unpack', 'clean', '1 % garbage'))
    return (f'the decoder handles {clean[0]:,.0f} frames/s on a clean stream and '
            f'{garbage[1]:,.0f} with 1 % garbage ({clean[0] / 50_000:.0f}x the 50,000 '
            f'target; {clean[1]:.2f}x a bare struct unpack without search or CRC, '
            f'{bare[0]:,.0f} frames/s).\n')


def sensor_node() -> str:
    text = kept_text('bench_sensor_node.txt')
    node = numbers_in(line_starting(text, 'teensy_node'))
    ratio = numbers_in(line_starting(text, 'p99 node / reference'))[0]
    return (f'Through `teensy_node` at 350 Hz, a frame written to the pty arrives as an Imu '
            f'message with p50 {node[0]:.2f} ms and p99 {node[1]:.2f} ms (target p99 < 5 ms; '
            f'{ratio:.1f}x a bare pyserial read of the same stream).\n')


def observers() -> str:
    text = kept_text('bench_observers.txt')
    ref, view, watch = (numbers_in(line_starting(text, key)) for key in
                        ('nothing beside', 'tactex view', 'tactex status'))
    verdict = 'under' if view[5] < 1.0 else 'over'
    return (f'What watching costs `teensy_node` at 350 Hz (frame written -> Imu received; '
            f'median p99 of 3 interleaved rounds, `python bench/bench_observers.py`): '
            f'{ref[1]:.2f} ms with nothing beside it (rounds {ref[2]:.2f}-{ref[3]:.2f}); '
            f'{watch[1]:.2f} ms with `tactex status` and `tactex watch` running '
            f'({watch[5]:+.2f} ms); {view[1]:.2f} ms with the live view forwarding at its '
            f'default `max_rate_hz` (60) to a subscribed WebSocket client ({view[5]:+.2f} ms, '
            f'rounds {view[2]:.2f}-{view[3]:.2f}: {verdict} the 1 ms target on 2 shared cores, '
            f'where the node, the view, the client and the emulator compete).\n')


def madgwick() -> str:
    data = kept_json('madgwick.json')
    cost = {row.split('|')[1].strip(): numbers_in(row.split('|')[2])
            for row in kept_text('madgwick.md').splitlines()
            if row.startswith('| tactex ') or row.startswith('| imufusion (C)')
            or row.startswith('| ahrs Madgwick')}
    rows = data['results']
    tuned = ('tactex', 'imufusion', 'ahrs')
    cases: dict[tuple, dict[str, float]] = {}
    for row in rows:
        if row['filter'] in tuned:
            error = row['rms_attitude_deg'] if row['mode'] == 'MARG' else row['rms_tilt_deg']
            cases.setdefault((row['bias'], row['rate_hz'], row['mode'], row['motion']),
                             {})[row['filter']] = error
    wins = sum(min(errors, key=errors.get) == 'tactex' for errors in cases.values())
    lost = [f'{motion}, {rate:g} Hz, {mode}, {bias} ({min(errors, key=errors.get)})'
            for (bias, rate, mode, motion), errors in cases.items()
            if min(errors, key=errors.get) != 'tactex']
    lines = ['| gyro bias | mode | tactex | imufusion 1.3.3 | ahrs 0.4.0 |',
             '|---|---|---|---|---|']
    for bias in dict.fromkeys(row['bias'] for row in rows):
        for mode in ('IMU', 'MARG'):
            means = [np.mean([errors[name] for (b, _, m, _), errors in cases.items()
                              if b == bias and m == mode]) for name in tuned]
            lines.append(f'| {bias} | {mode} | ' + ' | '.join(f'{v:.2f}' for v in means) + ' |')
    gains = {name: ' / '.join(f'{data["tuned"][name][mode]["gain"]:g}' for mode in ('IMU',
                                                                                  'MARG'))
             for name in tuned}
    grids = [data['tuned']['tactex'][mode]['grid'] for mode in ('IMU', 'MARG')]
    both = min(grids[0], key=lambda gain: grids[0][gain] + grids[1][gain])
    default = (f'Our default gain, {data["default_gain"]:g}, '
               + ('is' if float(both) == data['default_gain'] else 'is not')
               + f' the one of least mean error over both modes on the tuning seed ({both}). ')
    stream = cost['tactex streaming (Python)'][0]
    return (f'The filter costs {stream:.2f} us per sample streaming and '
            f'{cost["tactex batch (numba)"][0]:.3f} us in the batch path '
            f'({stream / cost["tactex batch (numba)"][0]:.0f}x less; imufusion\'s C code '
            f'{cost["imufusion (C)"][0]:.2f} us, ahrs {cost["ahrs Madgwick"][0]:.1f} us). '
            f'Accuracy on five seeded motions at 120 and 350 Hz, IMU and MARG, without and '
            f'with a 0.6 deg/s gyro bias, every filter with its gain grid-tuned on seed '
            f'{data["tuning_seed"]} and scored on seed {data["scored_seed"]} (IMU / MARG '
            f'gains: tactex {gains["tactex"]}, imufusion {gains["imufusion"]}, ahrs '
            f'{gains["ahrs"]}; what each was given is in `bench/results/madgwick.md`): mean '
            f'RMS error (deg; tilt for IMU, full attitude for MARG) after '
            f'{data["settle_s"]:g} s:\n\n' + '\n'.join(lines) + '\n\n'
            + default + f'Ours has the lowest error in {wins} of {len(cases)} cases; the '
            f'others: ' + ('; '.join(lost) if lost else 'none') + '.\n')


def driver() -> str:
    text = kept_text('bench_driver.txt')
    pings = numbers_in(line_starting(text, '5 unicast pings'))
    cycle = numbers_in(line_starting(text, 'sync read'))
    loop = numbers_in(line_starting(text, 'arm_driver 100 Hz loop'))
    return (f'- `python bench/bench_driver.py`: a full cycle (sync read of 5 servos + sync '
            f'write) takes {cycle[-2]:.2f} ms median, p99 {cycle[-1]:.2f} ms (target <= 2 ms; '
            f'{cycle[-2] / pings[-2]:.2f}x the time of five unicast pings); the 100 Hz '
            f"loop's |period - 10 ms| is {loop[-2]:.3f} ms median, p99 {loop[-1]:.2f} ms "
            f'(target < 2 ms).\n')


def sim() -> str:
    data = kept_json('sim.json')
    parts = [f'{name} {row["real_time_factor"]:.1f}x real time ({row["sensor_rate_hz"]:g} Hz, '
             f'{row["step_ms"]:.2f} ms steps; physics and control alone '
             f'{row["physics_alone_factor"]:.1f}x)' for name, row in data.items()]
    return (f'- `python bench/bench_sim.py`: {"; ".join(parts)}. Targets: probe 20x, the '
            f'texture scene with every effect 5x.\n')


def kinematics() -> str:
    data = kept_json('kinematics.json')
    sentences = []
    for use, (analytic, numeric) in data.items():
        sentences.append(f'{use}, {analytic["solves_per_s"]:,.0f} solves/s against '
                         f'{numeric["solves_per_s"]:,.0f} for {numeric["solver"]} '
                         f'({analytic["solves_per_s"] / numeric["solves_per_s"]:.0f}x; it '
                         f'missed {numeric["misses"]} of {numeric["targets"]} targets by more '
                         f'than 1 um, the analytic IK {analytic["misses"]})')
    return '- `python bench/bench_kinematics.py`: ' + '; '.join(sentences) + '.\n'


def sim_collect() -> str:
    data = kept_json('sim_collect.json')
    one, two = data['runs']['1'], data['runs']['2']
    same = 'byte for byte the same bags' if data['same_bags'] else '**different bags**'
    return (f'- `python bench/bench_collect.py --sweeps {data["sweeps"] // 12}`: '
            f'`tactex sim collect` recorded the {data["sweeps"]} sweeps in {one / 60:.1f} min '
            f'with one worker and {two / 60:.1f} min with two (a local Ray instance, its start '
            f'included) in the same run: {data["speedup"]:.2f}x on the 2 cores of this '
            f'machine, {same} (load average {data["load_before"]:.1f} before, '
            f'{data["load_after"]:.1f} after; `bench/results/sim_collect.json`).\n')


def online_latency() -> str:
    data = kept_json('online_latency.json')
    rows = data['rows']
    groups: dict[tuple[str, str], list[dict]] = {}
    for row in rows:
        groups.setdefault((row['model'], row['runtime_used']), []).append(row)

    def span(values: list[float]) -> str:
        return f'{min(values):.1f}-{max(values):.1f}'
    lines = ['| model | runtime | configurations | p50 ms | p99 ms | node p99 ms | bare model '
             'p50 ms | dropped |', '|---|---|---|---|---|---|---|---|']
    for (model, runtime), found in groups.items():
        lines.append(f'| {model} | {runtime} | {len(found)} | '
                     f'{span([r["p50_ms"] for r in found])} | '
                     f'{span([r["p99_ms"] for r in found])} | '
                     f'{span([r["node_p99_ms"] for r in found])} | '
                     f'{span([r["bare_p50_ms"] for r in found])} | '
                     f'{sum(r["dropped"] for r in found)} |')
    cnn = [r for r in rows if r['family'] == 'cnn']
    fast = [r for r in rows if r['family'] in ('cnn', 'minirocket')]
    dropped_350 = sum(r['dropped'] for r in rows if r['rate_hz'] == 350.0)
    estimates = [r['windows'] for r in rows]
    windows = sorted({r['window'] for r in rows})
    rates = sorted({r['rate_hz'] for r in rows})
    return ("End-to-end latency, a window's last sample arriving to its estimate (`python "
            f'bench/bench_online.py`, kept in `bench/results/online_latency.{{md,json}}`: '
            f'{len(rows)} configurations: {", ".join(dict.fromkeys(r["model"] for r in rows))} '
            'at windows '
            f'{", ".join(map(str, windows))} and {" and ".join(f"{r:g}" for r in rates)} Hz '
            f'with hop = window / 2, torch and onnxruntime side by side; {min(estimates)}-'
            f'{max(estimates)} estimates each, so a p99 is close to the largest of them; '
            'teensy_node and classifier_node SCHED_FIFO on one core; load average '
            f'{data["load_average_before"]:.1f} before, {data["load_average_after"]:.1f} after, '
            'other jobs on the same cores). Ranges are over windows, rates and runtimes '
            '(the per-configuration table is in the kept file):\n\n'
            + '\n'.join(lines) + '\n\n'
            f'Must: CNN p99 < 20 ms, met by {sum(r["p99_ms"] < 20.0 for r in cnn)} of '
            f'{len(cnn)} configurations; windows dropped at 350 Hz: {dropped_350}. Goal: p99 '
            f'< 5 ms for the CNN and MiniRocket, met by {sum(r["p99_ms"] < 5.0 for r in fast)} '
            f'of {len(fast)}. The bare model takes {span([r["bare_p50_ms"] for r in rows])} '
            'ms; the rest is the pipeline.\n')


def sweep() -> str:
    data = kept_json('sweep.json')

    def row(label: str, numbers: dict) -> str:
        return (f'| {label} | {numbers["contact"]:.1f} | {numbers["speed"]:.1f} '
                f'({numbers["arm_speed"]:.1f}) | {numbers["depth"]:.2f} '
                f'({numbers["planned"]:.2f}) | {numbers["bias"]:+.2f} | '
                f'{numbers["plan_ms"]:.0f} |')

    reference, default = data['reference'], data['probed_closed_loop']
    lines = ["| sweep | contact % (worst pathway) | worst speed window % (arm's edge) | "
             "press depth error rms mm (the plan's share) | mean mm | planning ms |",
             '|---|---|---|---|---|---|',
             row('scripted, on the true surface (reference)', reference),
             row('**probed in closed loop (MuJoCo, tactex_probe) every 10 mm, a point every '
                 '2 mm**', default)]
    lines += [row(f'{count} trajectory points, model probe every 10 mm', numbers)
              for count, numbers in data['by_samples'].items()]
    lines += [row(f'model probe every {step} mm, a point every 2 mm', numbers)
              for step, numbers in data['by_step_mm'].items()]
    return ('\n'.join(lines) + '\n\n' +
            f'"Model probe": contacts on the true surface with a probe\'s noise (1 mm, 2 deg), '
            f'for the curves. Along pathways the explorer probed in closed loop (the default '
            f'sweep, {data["pathways"]} pathways): {default["contact"]:.1f} % of the contact '
            f'segment in contact at worst (threshold 95 %, goal 99 %); the worst 0.25 s window '
            f'{default["speed"]:.1f} % off {data["speed_m_s"] * 1e3:g} mm/s (threshold 10 %, '
            f'goal 5 %; the edge where the arm holds it {default["arm_speed"]:.1f} %); the '
            f'press depth {default["depth"]:.2f} mm rms off the asked '
            f'{data["press_depth_m"] * 1e3:g} mm ({default["depth"] / reference["depth"]:.2f}x '
            f'the scripted sweep that knows the surface), of which the plan '
            f'{default["planned"]:.2f} mm; planned in {default["plan_ms"]:.0f} ms.\n')


def _disagreements(check: dict) -> str:
    """What differed in the live check's disagreements (windows cut apart or confidence)."""
    found = check.get('disagreements', [])
    if not found:
        return ''
    offsets = [abs(d['first_window_offset_ms']) for d in found
               if d['first_window_offset_ms'] is not None]
    same_class = sum(d['derived'] is not None and d['decided'] is not None
                     and d['derived']['class_id'] == d['decided']['class_id'] for d in found)
    shared = sum(d['shared_windows'] for d in found)
    return (f' (in the other {len(found)} the two nodes had cut their windows '
            + (f'{min(offsets):.1f}-{max(offsets):.1f} ms apart, ' if offsets else '')
            + f'{shared} windows shared; {same_class} of them decided the same class)')


def online_accuracy() -> str:
    """classifier_node's live decisions on held-out sweeps, per model, against contact time."""
    data = kept_json('online_accuracy.json')
    deep = data.get('deep_training', {})
    parts = []
    for model, result in data['models'].items():
        live, offline, check = result['live'], result['offline'], result['live_check']
        default = live['thresholds'][f'{check["threshold"]:.10g}']
        best_threshold, best = max(live['thresholds'].items(),
                                   key=lambda item: item[1]['harmonic_mean'])
        first, whole = live['first_window'], live['whole_sweep']
        parts.append(
            f'{model} decides {100 * default["accuracy"]:.1f} % of the sweeps right at the '
            f'default threshold ({check["threshold"]:g}) after a median '
            f'{default["median_contact_s"]:.1f} s of contact (earliness '
            f'{default["earliness"]:.2f}; from its first window alone '
            f'{100 * first["accuracy"]:.1f} % after {first["median_contact_s"]:.1f} s, from '
            f'the whole sweep {100 * whole["accuracy"]:.1f} % after '
            f'{whole["median_contact_s"]:.1f} s; TEASER\'s harmonic mean is best, '
            f'{best["harmonic_mean"]:.2f}, at threshold {best_threshold}); offline on the '
            f'same bags {100 * offline["window_accuracy"]:.1f} % of windows and '
            f'{100 * offline["whole_sweep_accuracy"]:.1f} % of whole sweeps; the node run '
            f'live at the default threshold took the derived decision in {check["agree"]} of '
            f'{check["sweeps"]} sweeps' + _disagreements(check) + '.')
    training = (f' Deep models trained with the `{deep["profile"]}` profile, '
                f'{deep["scaling"]} scaling, at most {deep["epochs"]} epochs.' if deep else '')
    models = ','.join(data['models'])
    return (f'Accuracy against contact time, live, on the physical sensor model (`python '
            f'bench/bench_online_accuracy.py --train-sweeps {data["train_sweeps_per_texture"]}'
            f' --test-sweeps {data["test_sweeps_per_texture"]} --models {models} --speed '
            f'{data["speed"]:g}`, kept in `bench/results/online_accuracy.{{md,json,png}}`): '
            f'held-out simulated sweeps of the 12 textures (another seed) played to two '
            f'running nodes as recorded; chance 8.3 %.{training}\n\n'
            + '\n\n'.join(f'- {part}' for part in parts) + '\n')
