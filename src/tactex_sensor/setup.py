# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Teensy wire protocol, serial publisher node and Madgwick orientation filter."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_sensor'

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
    description='Teensy wire protocol, serial publisher node and Madgwick orientation filter.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'teensy_node = tactex_sensor.teensy_node:main',
            'madgwick_node = tactex_sensor.madgwick_node:main',
        ],
    },
)
