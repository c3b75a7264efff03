"""The docs site builds, and every Python block of the docs runs as written."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)
#: Pages whose code needs the example plugin installed.
NEEDS_PLUGIN = {"plugins.md"}


def _pages():
    return sorted(p for p in DOCS.glob("*.md")) + [ROOT / "README.md"]


def _code(page: Path) -> str:
    return "\n".join(BLOCK.findall(page.read_text(encoding="utf-8")))


@pytest.mark.parametrize("page", [p for p in _pages() if p.name not in NEEDS_PLUGIN and _code(p)], ids=lambda p: p.name)
def test_python_blocks_run(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # figures and files the examples write land here
    exec(compile(_code(page), str(page), "exec"), {"__name__": "__docs__"})


@pytest.mark.slow
def test_plugin_page_runs_with_the_example_installed(tmp_path):
    site = tmp_path / "site"
    subprocess.run(
        [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", "--no-build-isolation", "--no-index",
         "--target", str(site), str(ROOT / "examples" / "footnav-plugin-example")],
        check=True, capture_output=True,
    )
    env = {k: v for k, v in os.environ.items() if k != "FOOTNAV_DISABLE_PLUGIN_AUTOLOAD"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(site), env.get("PYTHONPATH")]))
    proc = subprocess.run([sys.executable, "-c", _code(DOCS / "plugins.md")], env=env, cwd=tmp_path, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "example-gyro" in proc.stdout and "glrt" in proc.stdout


def test_component_pages_list_every_registered_component():
    sys.path.insert(0, str(DOCS))
    try:
        import hooks
    finally:
        sys.path.remove(str(DOCS))
    import footnav

    pages = hooks.component_pages()
    for kind, names in footnav.list_components().items():
        text = pages[hooks.KINDS[kind][0] + ".md"]
        for name in names:
            assert f"## `{name}`" in text
    assert "| `zupt_std_mps` | `0.01` | m/s |" in pages["estimators.md"]


def test_docs_site_builds_strictly(tmp_path):
    pytest.importorskip("mkdocs")
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
                          cwd=ROOT, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert (tmp_path / "site" / "reference" / "fusions" / "index.html").exists()
