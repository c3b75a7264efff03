"""The heading aid that changes nothing (the default)."""

from __future__ import annotations

from footnav.core.component import HeadingAid

__all__ = ["NoHeadingAid"]


class NoHeadingAid(HeadingAid):
    """No heading aid: the fusion's result as it is."""

    name = "none"
    online = True

    def correct(self, result, left, right=None):
        """``result`` unchanged, each foot's ``meta["heading_aid"]`` saying so."""
        return result
