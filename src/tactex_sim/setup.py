# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""MuJoCo bridge standing in for the arm and the tactile sensor: scenes, effects."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_sim'

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
    description='MuJoCo bridge standing in for the arm and the tactile sensor: scenes, effects.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'mujoco_bridge = tactex_sim.mujoco_bridge_node:main',
        ],
    },
)
