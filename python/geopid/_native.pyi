# Both builds of the extension have the same interface: `ext` is either.
from . import _geopid as ext

__all__ = ["ext"]
