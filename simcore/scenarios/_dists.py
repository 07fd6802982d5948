"""The distributions of a scenario spec: uniform, normal (clipped) and choice."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from simcore.scene.limits import MAX_CHOICES


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Uniform(Strict):
    """``{"uniform": [low, high]}``: every value in [low, high] equally likely."""

    uniform: tuple[float, float]

    @field_validator("uniform")
    @classmethod
    def _ordered(cls, v: tuple[float, float]) -> tuple[float, float]:
        if not all(math.isfinite(x) for x in v) or v[0] > v[1]:
            raise ValueError(f"needs finite low <= high, got [{v[0]:g}, {v[1]:g}]")
        if not math.isfinite(v[1] - v[0]):
            raise ValueError(f"high - low of [{v[0]:g}, {v[1]:g}] overflows; give a range "
                             "narrower than 1e308")
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

    @model_validator(mode="after")
    def _bounds(self) -> NormalParams:
        if self.min is not None and self.max is not None and self.min > self.max:
            raise ValueError(f"min {self.min:g} is above max {self.max:g}: every draw would "
                             "be one constant; give min <= max")
        return self


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
