# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What every tactex package shares: topics, QoS, channels, constants, node helpers."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_common'

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
    description='Shared by every tactex package: topics, QoS, channels, constants, node helpers.',
    license='Apache-2.0',
)
