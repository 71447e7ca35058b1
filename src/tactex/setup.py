# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Install the tactex bring-up package: the command line, launch/ and config/."""

from pathlib import Path

from setuptools import find_packages, setup

PACKAGE = 'tactex'
WORKSPACE = Path('..', '..')


def share_tree(folder: str) -> list[tuple[str, list[str]]]:
    """Map every file under the workspace's `folder` to share/tactex/`folder`."""
    entries: dict[str, list[str]] = {}
    for path in sorted((WORKSPACE / folder).rglob('*')):
        if path.is_file():
            target = Path('share', PACKAGE, path.parent.relative_to(WORKSPACE))
            entries.setdefault(str(target), []).append(str(path))
    return sorted(entries.items())


setup(
    name=PACKAGE,
    version='0.1.0',
    packages=find_packages(exclude=['test']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{PACKAGE}']),
        (f'share/{PACKAGE}', ['package.xml']),
        *share_tree('config'),
        *share_tree('launch'),
    ],
    install_requires=['setuptools'],
    zip_safe=True,
    maintainer='tactex maintainers',
    maintainer_email='maintainers@tactex.invalid',
    description='Bring-up: launch files, parameter files and the tactex command line.',
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'tactex = tactex.cli:main',
            'view_node = tactex.view.view_node:main',
        ],
    },
)
