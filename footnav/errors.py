"""footnav's errors and warnings under their public path: ``from footnav.errors import InvalidInputError``.

They are defined in the contracts layer, :mod:`footnav.core.errors`; these are the same objects.
"""

from footnav.core.errors import *  # noqa: F403
from footnav.core.errors import __all__  # noqa: F401
