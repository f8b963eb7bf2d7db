"""numba's cache of the kernels follows every kernel source, not only the caller's own."""

from colonna.core import jit_cache


def _kernels(tmp_path):
    src = tmp_path / "pkg"
    cache = src / "__pycache__"
    cache.mkdir(parents=True)
    caller, callee = src / "_kernels.py", src / "collar_law.py"
    caller.write_text("def step(): return law()\n")
    callee.write_text("def law(): return 1\n")
    cached = [cache / "_kernels.step-10.py311.nbi", cache / "_kernels.step-10.py311.1.nbc"]
    other = cache / "unrelated.f-3.py311.nbi"  # not a kernel module of the unit: kept
    for path in (*cached, other):
        path.write_bytes(b"machine code")
    return [caller, callee], cached, other


def test_an_edited_callee_drops_its_caller_s_cached_kernels(tmp_path):
    files, cached, other = _kernels(tmp_path)
    first = jit_cache.sources_digest(files)
    jit_cache.refresh(files, first)  # the first stamp: what is there is dropped once
    for path in cached:
        path.write_bytes(b"machine code")  # compiled again from these sources
    assert jit_cache.refresh(files, first) == []  # the same sources: the cache is kept
    assert all(path.is_file() for path in cached)

    files[1].write_text("def law(): return 2\n")  # only the callee changes
    edited = jit_cache.sources_digest(files)
    assert edited != first
    assert sorted(jit_cache.refresh(files, edited)) == sorted(cached)
    assert not any(path.is_file() for path in cached) and other.is_file()


def test_every_kernel_module_is_found_and_checks_the_cache_on_import():
    """Each module with a numba kernel is in the unit and calls ensure_fresh on import."""
    import importlib.util
    from pathlib import Path

    root = Path(importlib.util.find_spec("colonna").origin).parent.parent
    sources = {p.resolve() for p in jit_cache.kernel_sources()}
    assert len(sources) == len(jit_cache.KERNEL_MODULES)
    for path in sources:
        assert "ensure_fresh()" in path.read_text(), path
    for folder in ("colonna", "fem", "rigid", "meshes", "studies"):
        for path in (root / folder).rglob("*.py"):
            if "numba import" in path.read_text():
                assert path.resolve() in sources, f"{path}: a numba kernel outside the unit"
