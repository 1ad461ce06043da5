"""A full disk, a file-size limit, a read-only or unwritable directory: one line naming the path, exit 2,
nothing written before damaged, and --resume completes (gfmd_contact.app.safe_files).

The error is injected at every write of a run in turn (the k-th write of `safe_files`: a
temporary file or a CSV row half-written, then OSError), cycling through ENOSPC, EFBIG,
EROFS, EACCES and EDQUOT; then at each kind of write site of a study, a figure of `gfmd plot`,
of `gfmd run`, and the study report.
"""

import errno
import json
import os
from pathlib import Path

import pytest

import gfmd_contact.app.study
from gfmd_contact.app import checkpoints, safe_files
from gfmd_contact.cli import main

from test_run_dir import assert_same_run, scene, write_scene

ERRNOS = (errno.ENOSPC, errno.EFBIG, errno.EROFS, errno.EACCES, errno.EDQUOT)
WHY = {errno.ENOSPC: "no space left on the device (ENOSPC)", errno.EFBIG: "file larger than the file-size limit "
       "(ulimit -f) (EFBIG)", errno.EROFS: "read-only file system (EROFS)", errno.EACCES: "permission denied (EACCES)",
       errno.EDQUOT: "disk quota exceeded (EDQUOT)"}


class Injector:
    """Fail the k-th write of safe_files (or the first whose path matches `where`) after half of it."""

    def __init__(self, monkeypatch, k=None, code=errno.ENOSPC, where=None):
        self.k, self.code, self.where, self.n, self.hit = k, code, where, 0, None
        real_fdopen, real_open = os.fdopen, open

        class Os:
            def __getattr__(_, name):
                return getattr(os, name)

            @staticmethod
            def fdopen(fd, mode="r", *a, **kw):
                return self.wrap(real_fdopen(fd, mode, *a, **kw), os.readlink(f"/proc/self/fd/{fd}"))

        monkeypatch.setattr(safe_files, "os", Os())
        monkeypatch.setattr(safe_files, "open", lambda path, mode="r", *a, **kw:
                            self.wrap(real_open(path, mode, *a, **kw), path), raising=False)

    def wrap(self, fh, path):
        self.n += 1
        fail = self.n == self.k if self.where is None else (self.hit is None and self.where in str(path))
        if not fail:
            return fh
        self.hit = str(path)
        code = self.code

        class Failing:
            def __enter__(s):
                return s

            def __exit__(s, *exc):
                fh.close()

            def write(s, data):
                fh.write(data[: len(data) // 2])
                fh.flush()
                raise OSError(code, os.strerror(code))

            def __getattr__(s, name):
                return getattr(fh, name)

        return Failing()


def target_of(written):
    """The file a write was for: a temporary .NAME.XXXXXX.tmp of safe_files.atomic_write stands for NAME."""
    p = Path(written)
    return p.parent / p.name[1:-4].rsplit(".", 1)[0] if p.name.startswith(".") and p.name.endswith(".tmp") else p


def error_line(err):
    lines = [line for line in err.strip().splitlines() if line.startswith("gfmd: error:")]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.mark.parametrize("every_step", [True, False])
def test_every_write_of_a_run_fails_cleanly_then_resumes(tmp_path, monkeypatch, capsys, every_step):
    """every_step: a checkpoint at every step (CHECKPOINT_SECONDS = 0), else the default interval, where the steps
    between writes go to disk when the ramp stops (`gfmd_contact.app.checkpoints.checkpointing`)."""
    seconds = 0.0 if every_step else checkpoints.CHECKPOINT_SECONDS
    sc = scene(**{"surface.realizations": 2, "loading.steps": 4})
    path = write_scene(tmp_path, sc)
    ref = tmp_path / "ref"
    counter = Injector(monkeypatch)
    monkeypatch.setattr(checkpoints, "CHECKPOINT_SECONDS", seconds)
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot"]) == 0
    monkeypatch.undo()
    writes = counter.n
    # rows and states of every step (else of the first and the saved ones, and the last), the start and final files
    assert writes >= (2 * 5 * 2 + 7 if every_step else 2 * 2 * 2 + 7)
    for k in range(1, writes + 1):
        out = tmp_path / f"k{k}"
        code = ERRNOS[k % len(ERRNOS)]
        inject = Injector(monkeypatch, k=k, code=code)
        monkeypatch.setattr(checkpoints, "CHECKPOINT_SECONDS", seconds)
        capsys.readouterr()
        assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 2, k
        line = error_line(capsys.readouterr().err)
        assert line.startswith(f"gfmd: error: cannot write {target_of(inject.hit)}: "), (line, inject.hit)
        assert WHY[code] in line and f"continue with: gfmd run {path} --out {out} --resume" in line
        monkeypatch.undo()
        assert not list(out.rglob("*.tmp"))
        assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0, k
        assert_same_run(ref, out)


def test_unwritable_plot_folder(tmp_path, monkeypatch, capsys):
    sc = scene(**{"surface.realizations": 1, "loading.steps": 4})
    path = write_scene(tmp_path, sc)
    out = tmp_path / "o"
    Injector(monkeypatch, where="plots/.area_vs_delta", code=errno.EACCES)
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    line = error_line(capsys.readouterr().err)
    assert line.startswith(f"gfmd: error: cannot write {out}/plots/area_vs_delta.png: permission denied (EACCES)")
    assert f"the results in {out}/ are complete" in line and f"gfmd plot {out}" in line
    assert json.loads((out / "meta.json").read_text())["complete"] is True
    before = {p.name: p.read_bytes() for p in (out / "plots").glob("*.png")}  # written before the failure
    assert sorted(before) == ["area_vs_reduced_pressure.png", "pressure_vs_delta.png"]
    monkeypatch.undo()
    Injector(monkeypatch, where="plots/.interface", code=errno.ENOSPC)
    assert main(["plot", str(out)]) == 2
    line = error_line(capsys.readouterr().err)
    assert line == (f"gfmd: error: cannot write {out}/plots/interface_snapshot.png: no space left on the device "
                    "(ENOSPC)")
    assert all((out / "plots" / name).read_bytes() == data for name, data in before.items())  # intact
    monkeypatch.undo()
    assert main(["run", str(path), "--out", str(out), "--quiet", "--resume"]) == 0
    assert "drawing its figures again" in capsys.readouterr().err
    assert len(list((out / "plots").glob("*.png"))) == 5 and not list(out.rglob("*.tmp"))
    assert not (out / "plots" / safe_files.LOCK_NAME).exists()


def test_read_only_run_directory(tmp_path, monkeypatch, capsys):
    """The first write is the lock file: a read-only --out is refused before anything else."""
    path = write_scene(tmp_path, scene(**{"surface.realizations": 1}))
    out = tmp_path / "o"
    real = os.open

    def ro(p, flags, *a):
        if str(p).endswith(safe_files.LOCK_NAME):
            raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(p))
        return real(p, flags, *a)

    monkeypatch.setattr(os, "open", ro)
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    line = error_line(capsys.readouterr().err)
    assert line.startswith(f"gfmd: error: cannot write {out}/{safe_files.LOCK_NAME}: read-only file system (EROFS)")


def threaded(workers, scheduler):
    from distributed import Client, LocalCluster

    cluster = LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None)
    return Client(cluster), cluster


STUDY = """
name = "errors"
[scene]
surface = { length = 320e-9, nodes = 256, rolloff_wavelength = 160e-9, rollon_wavelength = 10e-9, realizations = 1 }
loading = { steps = 4, final_penetration = 8e-9, initial_separation = 20e-9 }
interface = { length_normal = 2.5e-9 }
output = { field_steps = 1 }
[axes]
"interface.phi_n_star" = [0.1, 0.2]
"""


@pytest.mark.parametrize("where, code", [("partial/realization0.csv", errno.ENOSPC),
                                         ("partial/.realization0.state", errno.EFBIG),
                                         ("/.curve.csv", errno.EDQUOT), ("/.study.csv", errno.ENOSPC),
                                         ("/.summary.nc", errno.EROFS), ("/.study.json", errno.EACCES)])
def test_study_write_sites_fail_cleanly_then_resume(tmp_path, monkeypatch, capsys, where, code):
    """The tasks run in this process (a threaded Dask cluster) so that the injection reaches them."""
    monkeypatch.setattr(gfmd_contact.app.study, "_client", threaded)
    study = tmp_path / "s.toml"
    study.write_text(STUDY)
    ref, out = tmp_path / "ref", tmp_path / "out"
    assert main(["study", "run", str(study), "--out", str(ref), "--quiet"]) == 0
    inject = Injector(monkeypatch, where=where, code=code)
    capsys.readouterr()
    assert main(["study", "run", str(study), "--out", str(out), "--quiet"]) == 2
    line = error_line(capsys.readouterr().err)
    assert inject.hit and line.startswith(f"gfmd: error: cannot write {out}/") and WHY[code] in line, line
    assert f"continue with: gfmd study run {study} --out {out}" in line
    monkeypatch.undo()
    monkeypatch.setattr(gfmd_contact.app.study, "_client", threaded)
    assert main(["study", "run", str(study), "--out", str(out), "--quiet"]) == 0
    for name in ("summary.csv", "summary.nc"):
        assert (ref / name).read_bytes() == (out / name).read_bytes()
    for task in (ref / "tasks").iterdir():
        assert_same_run(task, out / "tasks" / task.name)
    assert not list(out.rglob("*.tmp"))


@pytest.mark.parametrize("where, code", [("partial/realization0.csv", errno.ENOSPC), ("/.fields.npz", errno.EFBIG)])
def test_fe_run_write_errors_then_resume(tmp_path, monkeypatch, capsys, where, code):
    from test_cli_fe import fe_scene

    sc = fe_scene("cohesive", "self-affine").replace(**{"method.name": "fe", "loading.steps": 3})
    path = write_scene(tmp_path, sc)
    ref, out = tmp_path / "ref", tmp_path / "out"
    assert main(["run", str(path), "--out", str(ref), "--quiet", "--no-plot"]) == 0
    inject = Injector(monkeypatch, where=where, code=code)
    capsys.readouterr()
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot"]) == 2
    line = error_line(capsys.readouterr().err)
    assert line.startswith(f"gfmd: error: cannot write {target_of(inject.hit)}: {WHY[code]}"), line
    monkeypatch.undo()
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plot", "--resume"]) == 0
    assert_same_run(ref, out)
