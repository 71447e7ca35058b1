# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Fine-tuning: a deep model starts from the weights of a pretrained checkpoint."""

from __future__ import annotations

from pathlib import Path

from tactex_classify.errors import CheckpointError


def start_from(model, folder: str, name: str, window: int, channels: list[str],
               classes: list[str]) -> list[str]:
    """Load a pretrained checkpoint's weights into `model` (fine-tuning); the layers reset.

    The checkpoint must hold the same deep model for the same window and channels. With
    the same classes in the same order every weight is loaded; otherwise the output layers
    (`architectures.output_parameters`) keep their fresh initial weights and the rest is
    loaded. The scaler is not taken over: it is fitted on the new training windows.

    Raises:
        ValueError: the checkpoint is refused, not a deep model, or another model, window
            or channel list (each named with both values).
    """
    from tactex_classify.models.architectures import output_parameters
    from tactex_classify.models.checkpoint import load_checkpoint
    try:
        _, pretrained = load_checkpoint(Path(folder))
    except CheckpointError as err:
        raise ValueError(f'pretrained: {err}') from None
    if pretrained.CHECKPOINT_KIND != 'deep':
        raise ValueError(f'pretrained: {folder} holds {pretrained.model_name}, not a deep model; '
                         'fine-tuning starts from a deep checkpoint')
    for what, theirs, ours in (('model', pretrained.config.model, name),
                               ('window', pretrained.window_, window),
                               ('channels', pretrained.channels_, channels)):
        if theirs != ours:
            raise ValueError(f'pretrained: {folder} has {what} {theirs!r}, the training '
                             f'{ours!r}; fine-tune with the same {what}')
    state = pretrained.model_.state_dict()
    reset = [] if pretrained.classes_ == list(classes) else sorted(output_parameters(model))
    model.load_state_dict({key: value for key, value in state.items() if key not in reset},
                          strict=False)
    return reset
