# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bag-to-dataset conversion, texture models, training and the online classifier."""

from setuptools import find_packages, setup

PACKAGE = 'tactex_classify'

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
    description='Bag-to-dataset conversion, texture models, training and the online classifier.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'recorder_node = tactex_classify.recording.recorder_node:main',
            'classifier_node = tactex_classify.online.classifier_node:main',
            'identify_node = tactex_classify.identification.identify_node:main',
        ],
    },
)
