# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The parts of a deep model's training step: loss, clipping, optimizer, schedule, averaging.

`config` is a `deep_classifier.TrainingConfig`.
"""

from __future__ import annotations

import math


def batch_loss(loss_fn, expected, partners, weight: float):
    """The loss of a batch's logits: against its labels, or a mixup's two label sets."""
    def loss_of(logits):
        if partners is None:
            return loss_fn(logits, expected)
        return weight * loss_fn(logits, expected) + \
            (1 - weight) * loss_fn(logits, expected[partners])
    return loss_of


def training_step(model, inputs, loss_of, clip_norm: float):
    """Forward, backward and gradient clipping of one batch: its logits and loss.

    An ensemble (a model with `member_logits`) trains each member on its own loss with
    its own clipping, as if trained alone; its logits average the members' probabilities.
    """
    import torch
    if not hasattr(model, 'member_logits'):
        logits = model(inputs)
        loss = loss_of(logits)
        loss.backward()
        torch.nn.utils.clip_grad_norm_(model.parameters(), clip_norm)
        return logits, loss
    members = model.member_logits(inputs)
    losses = [loss_of(logits) for logits in members]
    torch.stack(losses).sum().backward()
    for member in model.members:
        torch.nn.utils.clip_grad_norm_(member.parameters(), clip_norm)
    probabilities = torch.stack([torch.softmax(logits.detach(), 1) for logits in members])
    return probabilities.mean(0).log(), torch.stack(losses).detach().mean()


def optimizer_for(model, config):
    """Adamax as the original, or AdamW with decoupled weight decay."""
    import torch
    if config.optimizer == 'adamw':
        return torch.optim.AdamW(model.parameters(), lr=config.learning_rate,
                                 weight_decay=config.weight_decay)
    return torch.optim.Adamax(model.parameters(), lr=config.learning_rate)


def schedule_for(optimizer, config, steps_per_epoch: int):
    """Per-step learning-rate factor: none, or linear warm-up then cosine decay to 0."""
    import torch
    if config.schedule == 'constant':
        return None
    warmup = config.warmup_epochs * steps_per_epoch
    total = max(config.epochs * steps_per_epoch, warmup + 1)

    def factor(step: int) -> float:
        if step < warmup:
            return (step + 1) / warmup
        return 0.5 * (1.0 + math.cos(math.pi * (step - warmup) / (total - warmup)))
    return torch.optim.lr_scheduler.LambdaLR(optimizer, factor)


def averaged_copy(model, config):
    """An exponential moving average of the weights and BatchNorm statistics, or None."""
    if not config.ema_decay:
        return None
    from torch.optim.swa_utils import AveragedModel, get_ema_multi_avg_fn
    return AveragedModel(model, multi_avg_fn=get_ema_multi_avg_fn(config.ema_decay),
                         use_buffers=True)
