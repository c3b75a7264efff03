"""The registry: which component class answers to which name, and which plugin registered it."""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Any, Iterator

from footnav.component import KINDS, Component, check_param_names
from footnav.errors import PluginError, UnknownComponentError

__all__ = ["Entry", "Registry"]


@dataclass(frozen=True)
class Entry:
    """One registered component: its kind, name, class, the plugin that registered it and the
    distribution (package) the plugin came from."""

    kind: str
    name: str
    cls: type[Component]
    plugin: str
    origin: str


class Registry:
    """Component classes by kind and name. Built by :func:`footnav.plugins.manager.build_registry`."""

    def __init__(self) -> None:
        self._entries: dict[str, dict[str, Entry]] = {kind: {} for kind in KINDS}
        #: ``(plugin name, distribution, error message)`` of plugins that failed to load.
        self.failed: list[tuple[str, str, str]] = []

    def add(self, kind: str, cls: Any, *, name: str | None, plugin: str, origin: str) -> Entry:
        """Validate and add one registration; PluginError says which plugin did what wrong."""
        base = KINDS[kind]
        if not (isinstance(cls, type) and issubclass(cls, base)):
            raise PluginError(
                f"plugin {plugin!r} ({origin}) registered {cls!r} as a {kind}, but a {kind} must be a "
                f"subclass of footnav.{base.__name__}"
            )
        name = name or cls.name
        if not name or not isinstance(name, str):
            raise PluginError(f"plugin {plugin!r} ({origin}) registered {cls.__name__} without a name")
        existing = self._entries[kind].get(name)
        if existing is not None:
            raise PluginError(
                f"{kind} name {name!r} is registered twice: by plugin {existing.plugin!r} ({existing.origin}, "
                f"{existing.cls.__qualname__}) and by plugin {plugin!r} ({origin}, {cls.__qualname__}); "
                "rename one of them"
            )
        entry = Entry(kind=kind, name=name, cls=cls, plugin=plugin, origin=origin)
        self._entries[kind][name] = entry
        return entry

    def names(self, kind: str) -> list[str]:
        return sorted(self._entries[kind])

    def __iter__(self) -> Iterator[Entry]:
        for kind in KINDS:
            for name in sorted(self._entries[kind]):
                yield self._entries[kind][name]

    def get(self, kind: str, name: str) -> Entry:
        """The entry for ``name``; UnknownComponentError lists what exists and the closest names."""
        if kind not in self._entries:
            raise UnknownComponentError(f"unknown component kind {kind!r}; kinds: {', '.join(KINDS)}")
        try:
            return self._entries[kind][name]
        except KeyError:
            available = self.names(kind)
            close = difflib.get_close_matches(str(name), available, n=2)
            hint = f" Did you mean {' or '.join(map(repr, close))}?" if close else ""
            raise UnknownComponentError(
                f"no {kind} named {name!r}; available: {', '.join(available) or 'none'}.{hint}"
            ) from None

    def create(self, kind: str, name: str, **params: Any) -> Component:
        """Instantiate ``name`` with ``params`` after checking the parameter names."""
        entry = self.get(kind, name)
        check_param_names(entry.cls, params)
        return entry.cls(**params)
