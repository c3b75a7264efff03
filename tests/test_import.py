"""What ``import footnav`` loads (issue 33): the package root, the pipeline factory and the data
types, not the analysis layer or the heavy third-party modules it uses only on demand. A test
on which modules load, never on how long the import takes (speed: benchmarks/bench_startup.py)."""

from __future__ import annotations

import importlib
import json
import subprocess
import sys

import pytest

from footnav._numba import LazyKernel, njit

#: Modules (and their submodules) that ``import footnav`` must leave unloaded.
NOT_AT_IMPORT = [
    "numba",  # footnav._numba makes each kernel on first use
    "sklearn",
    "hmmlearn",
    "scipy.signal",
    "scipy.optimize",
    "scipy.stats",
    "pandas",
    "matplotlib",
    "footnav.analysis",
    "footnav.analysis.comparison",
    "footnav.analysis.metrics",
    "footnav.analysis.evaluation",
]


def _loaded_after(code: str) -> set[str]:
    out = subprocess.run(
        [sys.executable, "-c", f"{code}; import json, sys; print(json.dumps(sorted(sys.modules)))"],
        capture_output=True,
        text=True,
        check=True,
    )
    return set(json.loads(out.stdout.strip().splitlines()[-1]))


def _offenders(loaded: set[str], names: list[str]) -> list[str]:
    return sorted(m for m in loaded for name in names if m == name or m.startswith(name + "."))


def test_import_footnav_leaves_the_heavy_modules_unloaded():
    loaded = _loaded_after("import footnav")
    assert "footnav.pipeline.factory" in loaded
    assert _offenders(loaded, NOT_AT_IMPORT) == []


def test_the_command_line_parser_leaves_the_heavy_modules_unloaded():
    """Building the parser (``footnav --help``, any command's set-up) imports no analysis."""
    loaded = _loaded_after("from footnav.cli import build_parser; build_parser()")
    assert _offenders(loaded, NOT_AT_IMPORT) == []


def test_writing_a_report_without_truth_leaves_pandas_and_the_analysis_unloaded(tmp_path):
    """``footnav run`` writes report.html from the stride table itself: a run without truth
    loads neither pandas nor the analysis layer (with scipy.optimize), which are 0.5 s of it."""
    code = (
        "import footnav; from footnav.data.results import write_results; "
        "rec = footnav.simulate('straight', distance_m=10, seed=1); "
        f"write_results(footnav.make_pipeline().run(rec.left), {str(tmp_path / 'res')!r}, html=True)"
    )
    loaded = _loaded_after(code)
    assert (tmp_path / "res" / "report.html").is_file()
    assert "matplotlib.figure" in loaded  # the figures were drawn: the report is the whole one
    assert _offenders(loaded, ["pandas", "scipy.optimize", "footnav.analysis"]) == []


def test_every_public_name_is_importable_and_listed():
    import footnav

    listed = dir(footnav)
    for name in footnav.__all__:
        assert name in listed, name
        assert getattr(footnav, name) is not None, name


@pytest.mark.parametrize(
    "name", ["evaluate", "evaluate_many", "EvaluationReport", "compare_detectors", "DetectorComparison"]
)
def test_a_lazy_name_is_the_analysis_object(name):
    import footnav

    module = {
        "evaluate_many": "footnav.analysis.batch",
        "compare_detectors": "footnav.analysis.comparison",
        "DetectorComparison": "footnav.analysis.comparison",
    }.get(name, "footnav.analysis.evaluation")
    assert getattr(footnav, name) is getattr(importlib.import_module(module), name)
    subprocess.run([sys.executable, "-c", f"from footnav import {name}"], check=True)


def test_an_unknown_name_is_an_attribute_error():
    import footnav

    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        footnav.nothing_here  # noqa: B018


# Kernels made on first use (footnav._numba.LazyKernel); no cache: these live in the tests.
@njit
def _double(x):
    return 2.0 * x


@njit(inline="always")
def _plus_one(x):
    return x + 1.0


@njit
def _caller(x):
    return _double(x) + _plus_one(x)


@njit
def _square(x):
    return x * x


@njit
def _apply(f, x):
    return f(x)


def test_a_kernel_is_made_with_the_kernels_it_calls():
    """Module globals (pytest's collection may have made these already, reading attributes)."""
    assert _caller(1.0) == 4.0
    assert not isinstance(globals()["_double"], LazyKernel)  # numba compiled against the dispatcher
    assert _caller.signatures and _caller.py_func.__name__ == "_caller"  # the dispatcher's attributes


def test_a_kernel_is_made_with_the_kernels_in_its_closure():
    @njit
    def double(x):
        return 2.0 * x

    @njit(inline="always")
    def plus_one(x):
        return x + 1.0

    @njit
    def caller(x):
        """Doc."""
        return double(x) + plus_one(x)

    assert isinstance(caller, LazyKernel) and "not made yet" in repr(caller)
    assert caller.__name__ == "caller" and caller.__doc__ == "Doc."  # without making it
    assert "not made yet" in repr(caller)
    assert caller(1.0) == 4.0
    assert not any(isinstance(c.cell_contents, LazyKernel) for c in caller.py_func.__closure__)


def test_a_kernel_passed_to_a_kernel():
    assert _apply(_square, 3.0) == 9.0


#: The component families that export their classes (loaded on first look-up).
FAMILIES = {
    "detector": "footnav.detectors",
    "estimator": "footnav.estimators",
    "fusion": "footnav.fusion",
    "heading_aid": "footnav.heading_aids",
}


def test_a_family_package_exports_every_builtin_of_its_kind():
    from footnav.plugins.builtin import BUILTINS

    for kind, entries in BUILTINS.items():
        family = importlib.import_module(FAMILIES[kind])
        for _, ref in entries:
            module, cls = ref.split(":")
            assert cls in family.__all__, (kind, cls)
            assert getattr(family, cls) is getattr(importlib.import_module(module), cls), (kind, cls)


def test_importing_a_family_loads_none_of_its_components():
    loaded = _loaded_after("import footnav.detectors, footnav.estimators, footnav.fusion")
    assert (
        _offenders(
            loaded,
            [
                "footnav.detectors.hmm",
                "footnav.detectors.adaptive",
                "footnav.estimators.ekf",
                "footnav.fusion.particle",
                "sklearn",
                "hmmlearn",
            ],
        )
        == []
    )


def test_the_public_errors_module_is_the_contracts_layers():
    """``footnav.errors`` is the public path of :mod:`footnav.core.errors`: the same objects, all
    of them, so ``except footnav.errors.InvalidInputError`` catches what the code raises."""
    import footnav.core.errors as core_errors
    import footnav.errors as public

    assert public.__all__ == core_errors.__all__
    assert all(getattr(public, name) is getattr(core_errors, name) for name in core_errors.__all__)
