"""Loading plugins: the built-ins, then third-party packages through the ``footnav`` entry points.

Each entry point is loaded on its own: one that fails to import, that implements a misspelt hook,
or that registers a name already taken (or something that is not a component), becomes a
:class:`~footnav.core.errors.PluginWarning` naming it, and the others still load.
Set ``FOOTNAV_DISABLE_PLUGIN_AUTOLOAD=1`` to load the built-ins only (the test suite does).
"""

from __future__ import annotations

import importlib.metadata
import os
from collections.abc import Iterable
from types import ModuleType

import pluggy

from footnav.core.errors import PluginError, PluginWarning
from footnav.core.warning_log import warn
from footnav.plugins import hookspecs
from footnav.plugins.registry import Registry

__all__ = ["build_registry", "get_registry", "reset_registry", "AUTOLOAD_ENV"]

AUTOLOAD_ENV = "FOOTNAV_DISABLE_PLUGIN_AUTOLOAD"
_HOOK_OF_KIND = {
    "detector": "footnav_register_detectors",
    "estimator": "footnav_register_estimators",
    "fusion": "footnav_register_fusions",
    "heading_aid": "footnav_register_heading_aids",
}
_registry: Registry | None = None


def _new_manager() -> pluggy.PluginManager:
    pm = pluggy.PluginManager(hookspecs.PROJECT)
    pm.add_hookspecs(hookspecs)
    return pm


def _register_checked(pm: pluggy.PluginManager, plugin: object, name: str, origin: str, registry: Registry) -> bool:
    """Register one plugin; a misspelt or malformed hook becomes a warning naming it."""
    try:
        pm.register(plugin, name=name)
        pm.check_pending()
    except (pluggy.PluginValidationError, ValueError) as exc:
        if pm.is_registered(plugin):
            pm.unregister(plugin)
        registry.failed.append((name, origin, str(exc)))
        warn(f"footnav plugin {name!r} ({origin}) is invalid and was skipped: {exc}", PluginWarning, stacklevel=3)
        return False
    return True


def build_registry(
    plugins: Iterable[ModuleType | object] = (), *, builtins: bool = True, autoload: bool | None = None
) -> Registry:
    """A fresh registry from the built-ins, ``plugins`` (objects with hook implementations) and,
    unless disabled, the installed ``footnav`` entry points.

    Parameters
    ----------
    plugins
        Extra plugin objects (modules or instances) to register, origin ``"<direct>"``; tests use
        this to register a plugin without installing it.
    builtins
        Register footnav's own components.
    autoload
        Load installed entry points; default: yes unless ``FOOTNAV_DISABLE_PLUGIN_AUTOLOAD`` is set.
    """
    if autoload is None:
        autoload = not os.environ.get(AUTOLOAD_ENV)
    registry = Registry()
    pm = _new_manager()
    origins: dict[str, str] = {}
    if builtins:
        from footnav.plugins import builtin

        pm.register(builtin, name="footnav.builtin")
        origins["footnav.builtin"] = "footnav"
    for plugin in plugins:
        name = getattr(plugin, "__name__", None) or type(plugin).__name__
        if _register_checked(pm, plugin, name, "<direct>", registry):
            origins[name] = "<direct>"
    if autoload:
        for ep in importlib.metadata.entry_points(group=hookspecs.ENTRY_POINT_GROUP):
            dist = ep.dist.name if ep.dist is not None else "unknown distribution"
            if pm.get_plugin(ep.name) is not None:
                continue
            try:
                module = ep.load()
            except Exception as exc:  # any import-time failure of someone else's code
                registry.failed.append((ep.name, dist, f"{type(exc).__name__}: {exc}"))
                warn(
                    f"footnav plugin {ep.name!r} from {dist} failed to import and was skipped: "
                    f"{type(exc).__name__}: {exc}",
                    PluginWarning,
                    stacklevel=2,
                )
                continue
            if _register_checked(pm, module, ep.name, dist, registry):
                origins[ep.name] = dist
    for kind, hook_name in _HOOK_OF_KIND.items():
        hook = getattr(pm.hook, hook_name)
        # one call per implementation, so that each registration is attributed to its plugin
        for impl in hook.get_hookimpls():
            origin = origins.get(impl.plugin_name, "<direct>")

            def register(
                cls: type | str,
                name: str | None = None,
                *,
                _kind: str = kind,
                _p: str = impl.plugin_name,
                _o: str = origin,
            ) -> None:
                try:
                    registry.add(_kind, cls, name=name, plugin=_p, origin=_o)
                except PluginError as exc:
                    if _o == "footnav":  # footnav's own registrations must not clash: a bug here
                        raise
                    # a clashing or malformed registration skips that component only: the
                    # built-ins and every other plugin keep working
                    registry.failed.append((_p, _o, str(exc)))
                    warn(f"footnav plugin {_p!r} ({_o}): {exc}; skipped", PluginWarning, stacklevel=2)

            try:
                impl.function(register=register)
            except PluginError:
                raise
            except Exception as exc:
                registry.failed.append((impl.plugin_name, origin, f"{type(exc).__name__}: {exc}"))
                warn(
                    f"footnav plugin {impl.plugin_name!r} ({origin}) failed in {hook_name}: {exc}",
                    PluginWarning,
                    stacklevel=2,
                )
    return registry


def get_registry() -> Registry:
    """The process-wide registry, built on first use."""
    global _registry
    if _registry is None:
        _registry = build_registry()
    return _registry


def reset_registry(registry: Registry | None = None) -> None:
    """Replace the process-wide registry (None: rebuild on next use)."""
    global _registry
    _registry = registry
