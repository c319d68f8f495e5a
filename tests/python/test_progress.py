"""Progress on long stages: on a terminal (a pseudo-terminal here) a bar with its percentage
and the time left; off a terminal nothing more unless --progress, and then one line per
tenth of each long stage (the label loop's too); Python's three-argument callback gets
("progress", stage, fraction) events, and one that raises stops the run. The mesh is the
same with or without.

Run by ctest (tests/CMakeLists.txt) with PYTHONPATH at the built module and MPUMESH_BIN at
the built program."""
import os
import pty
import re
import subprocess

import nibabel
import numpy as np
import pytest

import mpumesh

BIN = os.environ["MPUMESH_BIN"]
SPACING = (0.6, 0.6, 1.2)


def ball_array():
    z, y, x = np.meshgrid(*(np.arange(n, dtype=float) for n in (16, 30, 30)), indexing="ij")
    x, y, z = x * SPACING[0], y * SPACING[1], z * SPACING[2]
    return np.where((x - 9) ** 2 + (y - 9) ** 2 + (z - 9) ** 2 < 36, 1000.0, 0.0).astype(np.float32)


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    d = tmp_path_factory.mktemp("progress")
    affine = np.diag([*SPACING, 1.0])
    nibabel.save(nibabel.Nifti1Image(np.transpose(ball_array(), (2, 1, 0)), affine), str(d / "ball.nii.gz"))
    labels = np.where(ball_array() > 0, 1, 0).astype(np.int16)
    labels[:, :, 15:] *= 2
    nibabel.save(nibabel.Nifti1Image(np.transpose(labels, (2, 1, 0)), affine), str(d / "labels.nii.gz"))
    return d


def run_cli(args):
    return subprocess.run([BIN, *args], capture_output=True, text=True)


def tenth_lines(stderr):
    """(stage, percent) of each --progress line."""
    return [(m.group(1), int(m.group(2))) for m in re.finditer(r"^  (\S.*?) (\d+)%$", stderr, re.M)]


def test_python_gets_fractions_of_each_long_stage():
    events = []
    mpumesh.run(ball_array(), spacing=SPACING, threshold=500, particles=1500, backend="cpu", volume=True,
                progress=lambda event, stage, fraction=None: events.append((event, stage, fraction)))
    fractions = {}
    for event, stage, fraction in events:
        if event == "progress":
            assert 0 <= fraction <= 1
            fractions.setdefault(stage, []).append(fraction)
    assert set(fractions) == {"particles", "triangulate", "optimize", "volume mesh"}, fractions.keys()
    for stage, f in fractions.items():
        assert f[-1] == 1 and len(f) >= 2, (stage, f)
    # Each arrives between its stage's begin and end.
    begin = events.index(("begin", "particles", None))
    end = events.index(("end", "particles", None))
    assert all(s == "particles" for e, s, _ in events[begin + 1:end] if e == "progress")


def test_a_callback_that_raises_on_a_fraction_stops_the_run():
    def stop(event, stage, fraction=None):
        if event == "progress" and stage == "triangulate":
            raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        mpumesh.run(ball_array(), spacing=SPACING, threshold=500, particles=1500, backend="cpu", progress=stop)


def test_off_a_terminal_lines_per_tenth_only_with_progress(scans, tmp_path):
    plain = run_cli(["run", str(scans / "ball.nii.gz"), "--threshold", "500", "--particles", "1500", "--backend",
                     "cpu", "-o", str(tmp_path / "plain.ply")])
    assert plain.returncode == 0 and plain.stderr == "", plain.stderr
    told = run_cli(["run", str(scans / "ball.nii.gz"), "--threshold", "500", "--particles", "1500", "--backend",
                    "cpu", "-o", str(tmp_path / "told.ply"), "--volume", str(tmp_path / "told.msh"), "--progress"])
    assert told.returncode == 0, told.stderr
    lines = tenth_lines(told.stderr)
    assert len(lines) == len(told.stderr.splitlines()), told.stderr
    for stage in ("particles", "triangulate", "optimize", "volume mesh"):
        percents = [p for s, p in lines if s == stage]
        assert percents and percents[-1] == 100 and percents == sorted(set(percents)), (stage, percents)
        assert all(p % 10 == 0 for p in percents)
    assert (tmp_path / "plain.ply").read_bytes() == (tmp_path / "told.ply").read_bytes()


def test_the_label_loop_and_tetmesh_report_their_tenths(scans, tmp_path):
    r = run_cli(["run", str(scans / "labels.nii.gz"), "--labels", "all", "--particles", "1500", "--backend", "cpu",
                 "-o", str(tmp_path / "complex.ply"), "--progress"])
    assert r.returncode == 0, r.stderr
    assert [p for s, p in tenth_lines(r.stderr) if s == "labels"] == [50, 100], r.stderr
    t = run_cli(["tetmesh", str(tmp_path / "complex.ply"), "-o", str(tmp_path / "complex.vtu"), "--progress"])
    assert t.returncode == 0, t.stderr
    assert [p for s, p in tenth_lines(t.stderr) if s == "tetrahedralize"][-1] == 100, t.stderr


def test_on_a_terminal_a_bar_with_the_time_left(scans, tmp_path):
    leader, follower = pty.openpty()
    p = subprocess.Popen([BIN, "run", str(scans / "ball.nii.gz"), "--threshold", "500", "--particles", "3000",
                          "--backend", "cpu", "-o", str(tmp_path / "bar.ply")],
                         stdout=subprocess.DEVNULL, stderr=follower)
    os.close(follower)
    out = b""
    while True:
        try:
            chunk = os.read(leader, 4096)
        except OSError:  # the program closed the terminal
            break
        if not chunk:
            break
        out += chunk
    os.close(leader)
    assert p.wait() == 0
    text = out.decode()
    assert re.search(r"\r  particles +\[#*\.*\] +\d+%", text), text
    assert "s left" in text
    # Each stage ends on its own line with its time, the bar cleared.
    assert re.search(r"\r  particles +\d+\.\d+ s\x1b\[K", text), text
