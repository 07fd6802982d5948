"""The distributions of a scenario spec: uniform, normal (clipped) and choice."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, field_validator

#: Most values of a choice.
MAX_CHOICES = 1000


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Uniform(Strict):
    """``{"uniform": [low, high]}``: every value in [low, high] equally likely."""

    uniform: tuple[float, float]

    @field_validator("uniform")
    @classmethod
    def _ordered(cls, v: tuple[float, float]) -> tuple[float, float]:
        if not all(math.isfinite(x) for x in v) or v[0] > v[1]:
            raise ValueError("needs finite low <= high")
        return v

    def draw(self, rng: np.random.Generator) -> float:
        """One value."""
        return float(rng.uniform(self.uniform[0], self.uniform[1]))


class NormalParams(Strict):
    """Mean, standard deviation (≥ 0) and optional clipping bounds."""

    mean: float = Field(allow_inf_nan=False)
    std: float = Field(ge=0.0, allow_inf_nan=False)
    min: float | None = Field(None, allow_inf_nan=False)
    max: float | None = Field(None, allow_inf_nan=False)


class Normal(Strict):
    """``{"normal": {"mean": m, "std": s}}``, clipped to ``min``/``max`` when given."""

    normal: NormalParams

    def draw(self, rng: np.random.Generator) -> float:
        """One value."""
        p = self.normal
        value = float(rng.normal(p.mean, p.std))
        lo = -math.inf if p.min is None else p.min
        hi = math.inf if p.max is None else p.max
        return min(max(value, lo), hi)


class Choice(Strict):
    """``{"choice": [v1, v2, ...]}``: one of the values, equally likely."""

    choice: list[Any] = Field(min_length=1, max_length=MAX_CHOICES)

    def draw(self, rng: np.random.Generator) -> Any:
        """One value."""
        return self.choice[int(rng.integers(len(self.choice)))]
