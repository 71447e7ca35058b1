# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Contact detection, surface normals and the probe-and-broadcast node."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_probe'

setup(
    name=PACKAGE,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{PACKAGE}']),
        (f'share/{PACKAGE}', ['package.xml']),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='tactex maintainers',
    maintainer_email='maintainers@tactex.invalid',
    description='Contact detection, surface normals and the probe-and-broadcast node.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'probe_node = tactex_probe.probe_node:main',
        ],
    },
)
