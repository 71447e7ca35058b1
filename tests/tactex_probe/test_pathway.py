# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The pathway record: parameter ranges, record invariants, the JSON file round trip."""

import json
import math

import pytest

from tactex_probe.errors import ParameterError, PathwayError
from tactex_probe.pathway import (
    ContactStatus,
    PARAMETER_RANGES,
    Pathway,
    ProbeParameters,
    ProbeRecord,
)

GOAL = dict(start=(0.10, 0.0, 0.018), direction=(1.0, 0.0, 0.0), span=0.04, step=0.01,
            approach_height=0.02, descent_speed=0.005, max_descent_depth=0.02,
            force_limit=3.0)


def record(index, status=ContactStatus.OK, **changes):
    ok = status is ContactStatus.OK
    values = dict(index=index, status=status, stamp_ns=1_000_000_000 + index,
                  position=(0.1 + 0.01 * index, 0.0, 0.02),
                  normal=(0.6, 0.0, 0.8) if ok else (0.0, 0.0, 0.0),
                  force_proxy=1.5 if ok else 0.0, confidence=0.9 if ok else 0.0,
                  detail='' if ok else f'{status.name.lower()} here')
    values.update(changes)
    return ProbeRecord(**values)


def test_status_values_are_the_contact_message_codes():
    assert [(s.name, s.value) for s in ContactStatus] == [
        ('OK', 0), ('NO_CONTACT', 1), ('OVER_FORCE', 2), ('UNREACHABLE', 3),
        ('ESTIMATION_FAILED', 4)]


def test_probe_points_follow_the_direction_every_step():
    parameters = ProbeParameters(**GOAL)
    assert parameters.probe_count == 5
    assert parameters.probe_point(4) == pytest.approx([0.14, 0.0, 0.018])
    with pytest.raises(IndexError, match='outside 0..4'):
        parameters.probe_point(5)


def test_span_of_exact_multiple_of_step_keeps_the_last_point():
    assert ProbeParameters(**{**GOAL, 'span': 0.12, 'step': 0.01}).probe_count == 13


@pytest.mark.parametrize('name', sorted(PARAMETER_RANGES))
def test_parameters_outside_their_range_are_refused(name):
    allowed = PARAMETER_RANGES[name]
    for bad in (allowed.high * 2, -1.0, math.nan, math.inf):
        with pytest.raises(ParameterError, match=name):
            ProbeParameters(**{**GOAL, name: bad})


def test_direction_must_be_a_unit_vector():
    with pytest.raises(ParameterError, match='unit vector'):
        ProbeParameters(**{**GOAL, 'direction': (2.0, 0.0, 0.0)})
    with pytest.raises(ParameterError, match='3 finite numbers'):
        ProbeParameters(**{**GOAL, 'start': (0.1, math.nan, 0.0)})


def test_records_keep_their_invariants():
    with pytest.raises(ParameterError, match='unit normal'):
        record(0, normal=(0.0, 0.0, 2.0))
    with pytest.raises(ParameterError, match='zero normal'):
        record(0, ContactStatus.NO_CONTACT, normal=(0.0, 0.0, 1.0))
    with pytest.raises(ParameterError, match='confidence'):
        record(0, confidence=1.5)
    with pytest.raises(ParameterError, match='increase'):
        Pathway(ProbeParameters(**GOAL), (record(1), record(0)), 0)
    with pytest.raises(ParameterError, match='define only 5'):
        Pathway(ProbeParameters(**GOAL), (record(5),), 0)


def test_file_round_trip_keeps_every_status(tmp_path):
    probes = tuple(record(i, status) for i, status in enumerate(ContactStatus))
    pathway = Pathway(ProbeParameters(**GOAL), probes, 42_000_000_000)
    path = pathway.save(tmp_path / 'pathway.json')
    loaded = Pathway.load(path)
    assert loaded == pathway
    assert [p.index for p in loaded.contacts] == [0]
    assert loaded.outcomes == tuple(ContactStatus)
    assert sorted(p.name for p in tmp_path.iterdir()) == ['pathway.json']  # no temp left


def test_file_names_statuses_in_lower_case(tmp_path):
    path = Pathway(ProbeParameters(**GOAL), (record(0, ContactStatus.OVER_FORCE),), 0).save(
        tmp_path / 'p.json')
    data = json.loads(path.read_text())
    assert data['format'] == 'tactex-pathway' and data['version'] == 1
    assert data['probes'][0]['status'] == 'over_force'


@pytest.mark.parametrize('change, message', [
    (lambda d: d.update(version=2), 'version 1'),
    (lambda d: d.pop('probes'), r"top level: missing key\(s\) \['probes'\]; expected"),
    (lambda d: d.update(extra=1), r"top level: unknown key\(s\) \['extra'\]; expected"),
    (lambda d: (d.pop('probes'), d.update(extra=1)),
     r"missing key\(s\) \['probes'\]; unknown key\(s\) \['extra'\]; expected"),
    (lambda d: d['probes'][0].update(status='bent'), 'status must be one of'),
    (lambda d: d['probes'][0].update(normal=[0, 0, 3]), 'unit normal'),
    (lambda d: d['parameters'].update(step=0.0), 'step must be in'),
    # JSON reads a long whole number as an int past the float range
    (lambda d: d['parameters'].update(step=10**400), 'step must be in'),
    (lambda d: d['parameters'].update(start=[10**400, 0, 0]),
     'start must be 3 finite numbers'),
    (lambda d: d['probes'][0].update(confidence=10**400), 'confidence must be a finite number'),
    (lambda d: d.update(probes='none'), 'probes must be a list'),
])
def test_load_rejects_a_broken_file_naming_it(tmp_path, change, message):
    data = Pathway(ProbeParameters(**GOAL), (record(0),), 0).to_dict()
    change(data)
    path = tmp_path / 'broken.json'
    path.write_text(json.dumps(data))
    with pytest.raises(PathwayError, match=message) as caught:
        Pathway.load(path)
    assert 'broken.json' in str(caught.value)


def test_load_reports_missing_and_non_json_files(tmp_path):
    with pytest.raises(PathwayError, match='no pathway file'):
        Pathway.load(tmp_path / 'absent.json')
    (tmp_path / 'garbage.json').write_bytes(b'\xff{not json')
    with pytest.raises(PathwayError, match='not a readable JSON file'):
        Pathway.load(tmp_path / 'garbage.json')
