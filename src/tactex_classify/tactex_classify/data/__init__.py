# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings in, windows out: bag reading, stream alignment, datasets, imports, statistics.

- `bags`: a recording (rosbag2 folder) read into aligned channel arrays with its segments.
- `stream_alignment`: joining streams of different rates onto the leading one's stamps.
- `dataset`: windows, labels and recordings (`Dataset`, `convert`), the `.npz` format.
- `importers`: other people's data (the MUN dataset, CSV files) into the same format.
- `pickles`: a restricted unpickler for pandas frames in imported data.
- `signal_stats`: per-texture channel statistics and spectra (`tactex sim stats`).
"""

from tactex_classify.exports import lazy_exports

_EXPORTS = {'Recording': 'bags', 'read_recording': 'bags', 'segments': 'bags',
            'align': 'stream_alignment', 'Stream': 'stream_alignment',
            'Dataset': 'dataset', 'WindowCollector': 'dataset', 'convert': 'dataset',
            'FilterRule': 'dataset', 'import_mun': 'importers', 'import_csv': 'importers',
            'load_frame': 'pickles', 'RefusedPickle': 'pickles',
            'statistics': 'signal_stats'}
__all__ = sorted(_EXPORTS)
__getattr__ = lazy_exports(__name__, _EXPORTS)
