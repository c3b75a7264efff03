"""The heading aid that changes nothing (the default)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from footnav.core.component import HeadingAid

if TYPE_CHECKING:
    from footnav.core.types import FusionResult, ImuData

__all__ = ["NoHeadingAid"]


class NoHeadingAid(HeadingAid):
    """No heading aid: the fusion's result as it is."""

    name = "none"
    online = True

    def correct(self, result: FusionResult, left: ImuData, right: ImuData | None = None) -> FusionResult:
        """``result`` unchanged, each foot's ``meta["heading_aid"]`` saying so."""
        return result
