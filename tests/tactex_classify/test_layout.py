# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""tactex_classify's subpackages: each names its public API, and importing it is cheap."""

import importlib
import subprocess
import sys

import pytest

SUBPACKAGES = ('models', 'data', 'recording', 'training', 'online', 'evaluation')


@pytest.mark.parametrize('name', SUBPACKAGES)
def test_every_public_name_of_a_subpackage_resolves(name):
    package = importlib.import_module(f'tactex_classify.{name}')
    assert package.__all__ == sorted(package.__all__) and package.__all__
    for public in package.__all__:
        assert getattr(package, public) is not None, public
    with pytest.raises(AttributeError, match='has no attribute'):
        package.no_such_name  # noqa: B018


def test_importing_the_subpackages_loads_neither_torch_nor_rclpy():
    imports = '; '.join(f'import tactex_classify.{name}' for name in SUBPACKAGES)
    probe = (f'import sys; {imports}; '
             "print(sorted(m for m in ('torch', 'rclpy', 'sklearn') if m in sys.modules))")
    result = subprocess.run([sys.executable, '-c', probe], capture_output=True, text=True,
                            check=True)
    assert result.stdout.strip() == '[]'


def test_the_registry_is_the_one_list_of_model_names():
    from tactex_classify.models.architectures import MODELS
    from tactex_classify.models.registry import DEEP_MODELS
    assert list(MODELS) == list(DEEP_MODELS)
    assert all(MODELS[name].__name__ == name for name in DEEP_MODELS)


def test_every_baseline_has_a_checkpoint_kind_of_its_name():
    import importlib

    from tactex_classify.models.checkpoint import KINDS
    from tactex_classify.models.registry import BASELINES
    assert set(KINDS) == {'deep', *BASELINES}
    for name in BASELINES:
        module, cls = KINDS[name]
        assert getattr(importlib.import_module(module), cls).CHECKPOINT_KIND == name
