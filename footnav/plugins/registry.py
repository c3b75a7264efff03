"""The registry: which component class answers to which name, and which plugin registered it."""

from __future__ import annotations

import difflib
import importlib
from collections.abc import Iterator
from typing import Any

from footnav.core.component import KINDS, Component
from footnav.core.errors import PluginError, UnknownComponentError
from footnav.core.parameters import check_param_names

__all__ = ["Entry", "Registry"]


class Entry:
    """One registered component: its kind, name, class, the plugin that registered it and the
    distribution (package) the plugin came from.

    A class registered by reference (``"package.module:Class"``) is imported on first use of
    :attr:`cls`, so that building the registry imports no component it does not use.
    """

    __slots__ = ("_cls", "kind", "name", "origin", "plugin")

    def __init__(self, kind: str, name: str, cls: Any, plugin: str, origin: str) -> None:
        self.kind, self.name, self.plugin, self.origin = kind, name, plugin, origin
        self._cls = cls

    @property
    def cls(self) -> type[Component]:
        """The component class (imported on first look-up; errors name the plugin)."""
        if isinstance(self._cls, str):
            self._cls = _import_class(self._cls, self.kind, self.plugin, self.origin)
        return self._cls

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Entry):
            return NotImplemented
        return (self.kind, self.name, self.cls, self.plugin, self.origin) == (
            other.kind,
            other.name,
            other.cls,
            other.plugin,
            other.origin,
        )

    def __hash__(self) -> int:
        return hash((self.kind, self.name, self.plugin, self.origin))

    def __repr__(self) -> str:
        return (
            f"Entry(kind={self.kind!r}, name={self.name!r}, cls={self._cls!r}, plugin={self.plugin!r}, "
            f"origin={self.origin!r})"
        )


def _import_class(ref: str, kind: str, plugin: str, origin: str) -> type[Component]:
    """The class ``"package.module:Class"`` names, checked as :meth:`Registry.add` checks a class."""
    module, _, attr = ref.partition(":")
    cls = getattr(importlib.import_module(module), attr)
    _check_class(cls, kind, plugin, origin)
    return cls


def _label(cls: Any) -> str:
    return cls.rpartition(":")[2] if isinstance(cls, str) else cls.__qualname__


def _check_class(cls: Any, kind: str, plugin: str, origin: str) -> None:
    base = KINDS[kind]
    if not (isinstance(cls, type) and issubclass(cls, base)):
        raise PluginError(
            f"plugin {plugin!r} ({origin}) registered {cls!r} as a {kind}, but a {kind} must be a "
            f"subclass of footnav.{base.__name__}"
        )


class Registry:
    """Component classes by kind and name. Built by :func:`footnav.plugins.manager.build_registry`."""

    def __init__(self) -> None:
        self._entries: dict[str, dict[str, Entry]] = {kind: {} for kind in KINDS}
        #: ``(plugin name, distribution, error message)`` of plugins that failed to load.
        self.failed: list[tuple[str, str, str]] = []

    def add(self, kind: str, cls: Any, *, name: str | None, plugin: str, origin: str) -> Entry:
        """Validate and add one registration; PluginError says which plugin did what wrong.

        ``cls`` is a component class, or ``"package.module:Class"`` with ``name`` given: then the
        class is imported and checked on first use (:attr:`Entry.cls`).
        """
        if isinstance(cls, str):
            if ":" not in cls or not name:
                raise PluginError(
                    f"plugin {plugin!r} ({origin}) registered {cls!r}: a class given by reference is "
                    "'package.module:Class', with its name (register('pkg.mod:Cls', name='my-name'))"
                )
        else:
            _check_class(cls, kind, plugin, origin)
        name = name or cls.name
        if not name or not isinstance(name, str):
            raise PluginError(f"plugin {plugin!r} ({origin}) registered {cls.__name__} without a name")
        existing = self._entries[kind].get(name)
        if existing is not None:
            raise PluginError(
                f"{kind} name {name!r} is registered twice: by plugin {existing.plugin!r} ({existing.origin}, "
                f"{_label(existing._cls)}) and by plugin {plugin!r} ({origin}, {_label(cls)}); "
                "rename one of them"
            )
        entry = Entry(kind=kind, name=name, cls=cls, plugin=plugin, origin=origin)
        self._entries[kind][name] = entry
        return entry

    def names(self, kind: str) -> list[str]:
        """The registered names of ``kind``, sorted."""
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
