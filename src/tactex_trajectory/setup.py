# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Pathway to edge-offset sweep poses, timing and the trajectory executor."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_trajectory'

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
    description='Pathway to edge-offset sweep poses, timing and the trajectory executor.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'sweep_node = tactex_trajectory.sweep_node:main',
        ],
    },
)
