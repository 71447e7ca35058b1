# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Robot model of the arm and tactile module: geometry, URDF, MJCF, FK/IK."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_description'

setup(
    name=PACKAGE,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{PACKAGE}']),
        (f'share/{PACKAGE}', ['package.xml']),
        (f'share/{PACKAGE}/urdf', ['urdf/open_manipulator_x_tactile.urdf']),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='tactex maintainers',
    maintainer_email='maintainers@tactex.invalid',
    description='Robot model of the arm and tactile module: geometry, URDF, MJCF, FK/IK.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [],
    },
)
