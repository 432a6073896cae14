"""Faults on one machine (issue 24): a full disk or a read-only directory while a case, ``store.json``
or ``results.nc`` is written, and ``kill -9`` at several moments of a sweep.

A full disk and a read-only directory are simulated by making the system calls fail with ENOSPC or
EROFS/EACCES (monkeypatch): the tests run as root in CI, where ``chmod`` does not stop a write; the
real ``chmod`` test runs only as an ordinary user.
"""

from __future__ import annotations

import errno
import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from sweep_helpers import kill_after

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.io import files
from pdamper.io.files import atomic_write, remove_stale_temporaries
from pdamper.studies import ResultStore, SweepSpec, open_results, run_sweep


def _fail_with(code):
    def fail(*args, **kwargs):
        raise OSError(code, os.strerror(code))
    return fail


@pytest.mark.parametrize("call, code, words", [
    ("fsync", errno.ENOSPC, "no space left on the device"),
    ("replace", errno.EROFS, "the file system is read-only"),
    ("replace", errno.EACCES, "the directory is not writable"),
    ("replace", errno.EIO, "Input/output error"),
])
def test_a_refused_write_is_a_clear_error_and_leaves_the_old_file(tmp_path, monkeypatch, call, code, words):
    target = tmp_path / "store.json"
    target.write_text("old")
    monkeypatch.setattr(files.os, call, _fail_with(code))
    with pytest.raises(InputError, match=rf"cannot write .*store.json: {words}.*{errno.errorcode[code]}.*"
                                         "its previous content is unchanged"):
        atomic_write(target, "new")
    monkeypatch.undo()
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["store.json"]  # no temporary file left
    with pytest.raises(InputError, match="nothing was written"):
        monkeypatch.setattr(files.os, "fsync", _fail_with(errno.ENOSPC))
        atomic_write(tmp_path / "new.json", "x")
    monkeypatch.undo()
    assert not (tmp_path / "new.json").exists()


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root writes into a read-only directory")
def test_a_read_only_directory_for_real(tmp_path):
    d = tmp_path / "ro"
    d.mkdir()
    d.chmod(0o500)
    try:
        with pytest.raises(InputError, match="not writable"):
            atomic_write(d / "results.nc", b"x")
    finally:
        d.chmod(0o700)


def test_stale_temporaries_of_a_killed_writer_are_removed(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    stale = tmp_path / f".results.nc.{int(dead.stdout)}.0123abcd.tmp"
    mine = tmp_path / f".results.nc.{os.getpid()}.0123abcd.tmp"
    stale.write_bytes(b"half")
    mine.write_bytes(b"being written")
    assert remove_stale_temporaries(tmp_path) == [stale]
    assert mine.exists() and not stale.exists()


def _spec(cfg, strokes=(0.004, 0.012), seeds=(0,)):
    return SweepSpec(base=load_case(cfg), strokes=strokes, seeds=seeds)


def _fail_writes_of(monkeypatch, name, code=errno.ENOSPC):
    """atomic_write of the store (its own and the datasets' write, io.files.write_dataset) fails with
    ``code`` for files called ``name`` (others are written)."""
    from pdamper.studies import store as store_module

    real = store_module.atomic_write

    def atomic(path, data):
        if os.path.basename(path) == name or (name == "case" and str(path).endswith(".json")
                                              and "cases" in str(path) and not atomic.done):
            real_fsync = files.os.fsync
            monkeypatch.setattr(files.os, "fsync", _fail_with(code))
            try:
                return real(path, data)
            finally:
                monkeypatch.setattr(files.os, "fsync", real_fsync)
        if "cases" in str(path) and str(path).endswith(".json"):
            atomic.done = True
        return real(path, data)

    atomic.done = False
    monkeypatch.setattr(store_module, "atomic_write", atomic)
    monkeypatch.setattr(files, "atomic_write", atomic)


@pytest.mark.slow
def test_a_full_disk_while_results_nc_is_written_keeps_the_store_resumable(tiny_config, tmp_path, monkeypatch):
    # the probe of issue 24: the case files were written, then results.nc ended in a traceback
    store = tmp_path / "store"
    _fail_writes_of(monkeypatch, "results.nc")
    with pytest.raises(InputError, match=r"cannot write .*results.nc: no space left on the device \(ENOSPC\).*"
                                         r"keeps its 2 finished case\(s\).*re-run the same command on it to resume"):
        run_sweep(_spec(tiny_config), store, workers=1, progress=False, keep="none")
    monkeypatch.undo()
    assert not (store / "results.nc").exists() and not list(store.glob(".*.tmp"))
    assert len(ResultStore.open(store).records()) == 2  # readable: every finished case is there
    stamps = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    ds = run_sweep(_spec(tiny_config), store, workers=1, progress=False, keep="none")  # room again
    assert {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")} == stamps  # nothing recomputed
    assert np.isfinite(ds.eta_star.values).all()
    np.testing.assert_array_equal(open_results(store / "results.nc").eta_star.values, ds.eta_star.values)


@pytest.mark.slow
def test_a_full_disk_while_a_case_is_written_from_the_command_line(tiny_config, tmp_path, monkeypatch):
    from click.testing import CliRunner

    from pdamper.cli import main

    store = tmp_path / "store"
    args = ["sweep", str(tiny_config), "--strokes", "4mm,12mm", "--seeds", "1", "--workers", "1", "--out", str(store)]
    _fail_writes_of(monkeypatch, "store.json", code=errno.EROFS)
    out = CliRunner().invoke(main, args)
    assert out.exit_code == 2 and "Traceback" not in out.output, out.output
    assert "Error: cannot write" in out.output and "store.json: the file system is read-only (EROFS)" in out.output
    monkeypatch.undo()
    _fail_writes_of(monkeypatch, "case")  # the first case file fails: the disk fills during the sweep
    out = CliRunner().invoke(main, args)
    assert out.exit_code == 2 and "Traceback" not in out.output, out.output
    assert "no space left on the device (ENOSPC)" in out.output and "re-run the same command" in out.output
    monkeypatch.undo()
    out = CliRunner().invoke(main, args + ["--json"])
    assert out.exit_code == 0, out.output
    assert len(list((store / "cases").glob("*.json"))) == 2 and (store / "results.nc").exists()


# ----------------------------------------------------------------------------- kill -9

#: A sweep that kills itself (SIGKILL) in the middle of writing results.nc: the temporary file is
#: written whole, the rename not done (the worst moment for the result file).
_KILL_IN_RESULTS = textwrap.dedent("""
    import os, signal, sys
    from pdamper.io import files
    real = files.os.replace
    def replace(src, dst):
        if str(dst).endswith("results.nc"):
            os.kill(os.getpid(), signal.SIGKILL)
        return real(src, dst)
    files.os.replace = replace
    from pdamper.cli import main
    sys.argv = ["pdamper"] + sys.argv[1:]
    main()
""")


@pytest.mark.slow
def test_kill_minus_nine_at_several_moments_loses_nothing_and_recomputes_nothing(tiny_config, tmp_path):
    args = ["sweep", str(tiny_config), "--strokes", "2mm:12mm:4", "--seeds", "1", "--workers", "1", "--json"]
    undisturbed = tmp_path / "undisturbed"
    ref = subprocess.run([sys.executable, "-m", "pdamper.cli", *args, "--out", str(undisturbed)],
                         capture_output=True, text=True, timeout=300)
    assert ref.returncode == 0, ref.stderr
    store = tmp_path / "store"
    cmd = [sys.executable, "-m", "pdamper.cli", *args, "--out", str(store)]
    seen = {}
    for cases in (1, 3):  # after the first case, then after three
        got = kill_after(cmd, store, cases=cases)
        assert len(got) >= cases
        for name, blob in seen.items():
            assert got[name] == blob  # a case stored before a kill is never rewritten
        for blob in got.values():
            json.loads(blob)  # every stored case is whole
        seen = got
    # killed while results.nc is written: every case is stored, results.nc is not (or whole)
    killed = subprocess.run([sys.executable, "-c", _KILL_IN_RESULTS, *args, "--out", str(store)],
                            capture_output=True, text=True, timeout=300)
    assert killed.returncode == -9, killed.stderr
    assert not (store / "results.nc").exists() and list(store.glob(".results.nc.*.tmp"))
    cases = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    assert len(cases) == 4 and all(cases[k] == v for k, v in seen.items())
    # resumed: nothing recomputed, the stale temporary removed, the numbers of the undisturbed sweep
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")} == cases
    assert not list(store.glob(".*.tmp"))
    a, b = open_results(undisturbed / "results.nc"), open_results(store / "results.nc")
    for name in ("eta_star", "energy_per_cycle", "steps"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
