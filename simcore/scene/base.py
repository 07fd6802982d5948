"""Base model class and shared field types for the project model.

Every model is a :class:`psygnal.EventedModel` (a validated pydantic model that emits one
event per changed field), so that GUI views can listen to the same objects the CLI uses.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Annotated

from pydantic import ConfigDict, Field

if TYPE_CHECKING:
    # The pydantic mypy plugin does not see through psygnal's metaclass; type-check the
    # models as the pydantic models they are.
    from pydantic import BaseModel as EventedModel
else:
    from psygnal import EventedModel


class Model(EventedModel):
    """Validated, evented model: unknown fields, NaN and infinity are rejected."""

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
