"""Base model class and shared field types for the project model.

Models are validated pydantic models and treated as values: an edit builds a new project
(the GUI's document pushes it on its undo stack and emits one change signal), so the
models themselves emit no events.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field


class Model(BaseModel):
    """Validated model: unknown fields, NaN and infinity are rejected."""

    model_config = ConfigDict(
        extra="forbid",
        validate_assignment=True,
        allow_inf_nan=False,
        validate_default=True,
    )


Finite = Annotated[float, Field(allow_inf_nan=False)]
Positive = Annotated[float, Field(gt=0, allow_inf_nan=False)]
NonNegative = Annotated[float, Field(ge=0, allow_inf_nan=False)]
Fraction = Annotated[float, Field(ge=0, le=1, allow_inf_nan=False)]
Vec3 = tuple[Finite, Finite, Finite]
PositiveVec3 = tuple[Positive, Positive, Positive]
Vec2 = tuple[Finite, Finite]
