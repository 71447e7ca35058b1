# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Dynamixel Protocol 2.0 bus and arm driver node for the OpenMANIPULATOR-X."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_driver'

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
    description='Dynamixel Protocol 2.0 bus and arm driver node for the OpenMANIPULATOR-X.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'arm_driver = tactex_driver.arm_driver_node:main',
        ],
    },
)
