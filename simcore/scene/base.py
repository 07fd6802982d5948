"""Base model class and shared field types for the project model.

Models are validated pydantic models and treated as values: an edit builds a new project
(the GUI's document pushes it on its undo stack and emits one change signal), so the
models themselves emit no events.
"""

from __future__ import annotations

from typing import Annotated

from pydantic import AfterValidator, BaseModel, ConfigDict, Field


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

# --- physically bounded quantities ----------------------------------------------------------
# Values beyond these limits are refused where a project is validated: past them the float
# arithmetic of the sensors (phases 2π f τ, NUFFT points, render depth ranges) stops being
# meaningful, and some native libraries crash instead of raising.

#: Largest distance of anything from the world origin (m).
MAX_COORDINATE_M = 1e5
#: Largest and smallest object dimension (m).
MAX_SIZE_M = 1e4
MIN_SIZE_M = 1e-6
#: Largest linear speed of an object or the rig (m/s).
MAX_SPEED_MPS = 1e4
#: Largest angular speed (degrees per second) and Euler angle magnitude (degrees).
MAX_ANGULAR_SPEED_DPS = 1e5
MAX_ANGLE_DEG = 3600.0
#: Longest span of time a motion may refer to (s) and the shortest keyframe spacing (s).
MAX_TIME_S = 1e6
MIN_KEYFRAME_SPACING_S = 1e-6
#: Longest name (characters).
MAX_NAME_LENGTH = 4096

Coordinate = Annotated[float, Field(ge=-MAX_COORDINATE_M, le=MAX_COORDINATE_M,
                                    allow_inf_nan=False)]


def _at_least_min_size(value: float) -> float:
    if value < MIN_SIZE_M:
        raise ValueError(f"size {value:.3g} m is below the smallest allowed {MIN_SIZE_M:g} m")
    return value


Size = Annotated[float, Field(gt=0, le=MAX_SIZE_M, allow_inf_nan=False),
                 AfterValidator(_at_least_min_size)]
Angle = Annotated[float, Field(ge=-MAX_ANGLE_DEG, le=MAX_ANGLE_DEG, allow_inf_nan=False)]
Speed = Annotated[float, Field(ge=-MAX_SPEED_MPS, le=MAX_SPEED_MPS, allow_inf_nan=False)]
AngularSpeed = Annotated[float, Field(ge=-MAX_ANGULAR_SPEED_DPS, le=MAX_ANGULAR_SPEED_DPS,
                                      allow_inf_nan=False)]
Time = Annotated[float, Field(ge=0, le=MAX_TIME_S, allow_inf_nan=False)]
Position3 = tuple[Coordinate, Coordinate, Coordinate]
Rotation3 = tuple[Angle, Angle, Angle]
Velocity3 = tuple[Speed, Speed, Speed]
AngularVelocity3 = tuple[AngularSpeed, AngularSpeed, AngularSpeed]
Size3 = tuple[Size, Size, Size]


def check_name(name: str, what: str = "name") -> str:
    """Refuse names with control characters (NUL breaks HDF5 strings) or over the cap."""
    if len(name) > MAX_NAME_LENGTH:
        raise ValueError(f"{what} has {len(name)} characters; at most {MAX_NAME_LENGTH}")
    bad = next((c for c in name if ord(c) < 32 or ord(c) == 127), None)
    if bad is not None:
        raise ValueError(f"{what} contains the control character {bad!r}; use printable text")
    return name
