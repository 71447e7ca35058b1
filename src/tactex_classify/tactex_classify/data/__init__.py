# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings in, windows out: bag reading, stream alignment, datasets, imports, statistics.

- `sources`: what a recording is (rosbag2 folders, ROS 1 bags, lone MCAP and sqlite3 files)
  and one reader of its parts' messages; `inflation` bounds decompression; `ros1_index`
  opens a ROS 1 bag for a few topics; `mcap_index` reads MCAP message indexes.
- `topic_inventory`: a recording's topics, types, counts and rates, and what to name.
- `bags`: a recording read into aligned channel arrays with its segments.
- `decoder_process`: a recording's messages decoded in a second process.
- `bag_info`: what a recording holds (`tactex bag info`).
- `resampling`: a recording onto a uniform time grid at another rate.
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
