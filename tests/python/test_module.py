"""The Python module `mpumesh`: phantoms from numpy, a NIfTI read with nibabel, every
error path, and the same mesh bytes as the command line on the same input.

Run by ctest (tests/CMakeLists.txt) with PYTHONPATH at the built module and MPUMESH_BIN at
the built program."""
import os
import subprocess
import threading
import time

import nibabel
import numpy as np
import pytest

import mpumesh

BIN = os.environ["MPUMESH_BIN"]


def ball(shape=(12, 28, 30), spacing=(0.6, 0.6, 2.0), centre=(9.0, 8.0, 12.0), radius=6.0):
    """A ball with a linear edge one voxel wide, 1000 inside and -1000 outside, in (z, y, x)
    order; spacing and centre as (x, y, z)."""
    z, y, x = np.meshgrid(*(np.arange(n, dtype=float) for n in shape), indexing="ij")
    p = np.stack([x * spacing[0], y * spacing[1], z * spacing[2]], axis=-1)
    d = (radius - np.linalg.norm(p - np.array(centre), axis=-1)) / min(spacing)
    return (1000.0 * np.clip(d, -1, 1)).astype(np.float32)


def closed(result):
    """Each edge in exactly two faces, once each way."""
    f = result["faces"]
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    directed = {tuple(e) for e in edges.tolist()}
    return len(directed) == len(edges) and all((b, a) in directed for a, b in directed)


def test_meshes_a_phantom_from_numpy():
    r = mpumesh.run(ball(), spacing=(0.6, 0.6, 2.0), threshold=0, particles=1500, backend="cpu")
    v, f = r["vertices"], r["faces"]
    assert v.shape[1] == 3 and v.dtype == np.float64 and f.shape[1] == 3
    assert r["normals"].shape == v.shape and r["K"].shape == (len(v),)
    assert closed(r)
    radius = np.linalg.norm(v - np.array([9.0, 8.0, 12.0]), axis=1)
    assert abs(np.median(radius) - 6.0) < 0.15, np.median(radius)
    assert r["report"]["triangles"] == len(f)
    assert r["report"]["quality"]["closed"]
    assert r["report"]["segmentation"]["method"] == "threshold"
    # K of a 6 mm sphere is 1/36 per mm^2.
    assert abs(np.median(r["K"]) - 1 / 36) < 0.1 / 36


def test_same_bytes_as_the_command_line(tmp_path):
    vol = tmp_path / "ball.nii.gz"
    img = nibabel.Nifti1Image(np.transpose(ball(), (2, 1, 0)).astype(np.int16), np.diag([0.6, 0.6, 2.0, 1.0]))
    nibabel.save(img, vol)
    cli = tmp_path / "cli.ply"
    subprocess.run([BIN, "run", str(vol), "--threshold", "0", "--particles", "1500", "--backend", "cpu", "--quiet",
                    "-o", str(cli)], check=True)
    array, spacing, origin, direction = mpumesh.read_volume(str(vol))
    assert array.shape == (12, 28, 30)
    r = mpumesh.run(array, spacing=spacing, origin=origin, direction=direction, threshold=0, particles=1500,
                    backend="cpu")
    ours = tmp_path / "module.ply"
    mpumesh.write_mesh(str(ours), r)
    assert ours.read_bytes() == cli.read_bytes()


def test_a_nifti_read_with_nibabel_and_passed_as_an_array(tmp_path):
    vol = tmp_path / "ball.nii.gz"
    affine = np.array([[0.6, 0, 0, -4.0], [0, 0.6, 0, 7.5], [0, 0, 2.0, 30.0], [0, 0, 0, 1]])
    nibabel.save(nibabel.Nifti1Image(np.transpose(ball(), (2, 1, 0)).astype(np.int16), affine), vol)
    img = nibabel.load(vol)
    data = np.transpose(np.asarray(img.dataobj), (2, 1, 0))  # nibabel's (x, y, z) to (z, y, x)
    # nibabel's affine is RAS; mpumesh, like ITK and DICOM, works in LPS.
    lps = np.diag([-1.0, -1.0, 1.0]) @ img.affine[:3, :]
    spacing = np.linalg.norm(lps[:, :3], axis=0)
    r = mpumesh.run(data, spacing=spacing, origin=lps[:, 3], direction=lps[:, :3] / spacing, threshold=0,
                    particles=1500, backend="cpu")
    # The same volume through mpumesh's own reader.
    array, spacing, origin, direction = mpumesh.read_volume(str(vol))
    again = mpumesh.run(array, spacing=spacing, origin=origin, direction=direction, threshold=0, particles=1500,
                        backend="cpu")
    assert len(r["faces"]) == len(again["faces"])
    assert np.abs(r["vertices"] - again["vertices"]).max() < 1e-6
    # In LPS the ball's centre is at (-(-4 + 9), -(7.5 + 8), 30 + 12).
    assert np.allclose(r["vertices"].mean(axis=0), [-5.0, -15.5, 42.0], atol=0.2)


def test_remeshes_a_closed_mesh(tmp_path):
    r = mpumesh.run(ball(), spacing=(0.6, 0.6, 2.0), threshold=0, particles=1500, backend="cpu")
    again = mpumesh.remesh(r["vertices"], r["faces"], particles=800, backend="cpu")
    assert closed(again)
    assert again["report"]["input"]["kind"] == "mesh"
    assert abs(np.median(np.linalg.norm(again["vertices"] - [9.0, 8.0, 12.0], axis=1)) - 6.0) < 0.15


def test_label_maps_and_options_by_the_commands_names():
    labels = np.zeros((12, 28, 30), np.int16)
    labels[ball() > 0] = 3
    r = mpumesh.run(labels, spacing=(0.6, 0.6, 2.0), label=3, particles=1500, largest=1, no_self_intersections=True,
                    backend="cpu", threads=1)
    assert r["report"]["label"] == 3
    assert r["report"]["components_filter"]["kept"] == 1
    assert r["report"]["quality"]["self_intersections"] is None  # not checked


def test_progress_reaches_the_callback_and_the_gil_is_free():
    events, ticks = [], []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        mpumesh.run(ball(), spacing=(0.6, 0.6, 2.0), threshold=0, particles=1500, backend="cpu",
                    progress=lambda event, text: events.append((event, text, time.monotonic())))
    finally:
        done.set()
        t.join()
    stages = [text for event, text, _ in events if event == "begin"]
    assert stages[:4] == ["segment", "points", "fit", "particles"], stages
    # The other thread ran inside the stages, between the callbacks: with the GIL held
    # there it could not.
    begin = next(at for event, text, at in events if (event, text) == ("begin", "particles"))
    end = next(at for event, text, at in events if (event, text) == ("end", "triangulate"))
    inside = sum(begin < at < end for at in ticks)
    assert inside >= 0.2 * (end - begin) / 0.001, (inside, end - begin)


@pytest.mark.parametrize("call, words", [
    (lambda: mpumesh.run(np.zeros((4, 4)), spacing=(1, 1, 1)), "a 3-D array"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1)), "spacing: three numbers"),
    (lambda: mpumesh.run(ball(), spacing=(1, -1, 1)), "every value must be above 0"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), direction=np.eye(2)), "a 3 x 3 matrix"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), no_such_option=3), "no_such_option"),
    # Options named as Python spells them, not as the command line does.
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), particles=-5), "particles= must be between 1 and 10^8 (0: from "
                                                                   "particle_spacing="),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), particle_spacing=-1), "particle_spacing= must be positive"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), threshold=5000, backend="cpu"), "no voxel lies in the threshold"),
    (lambda: mpumesh.run(np.full((4, 4, 4), np.nan, np.float32), spacing=(1, 1, 1)), "NaN or infinite"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), labels="all", separate=True), "mesh a label on its own"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), volume="out.msh"), "volume: True or False"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), volume_background=True), "volume_background: applies to "
                                                                             "volume=True"),
    (lambda: mpumesh.run(ball(), spacing=(1, 1, 1), label=2), "not a label map"),
    (lambda: mpumesh.remesh(np.zeros((3, 3)), np.array([[0, 1, 2]])), "closed"),
    (lambda: mpumesh.remesh(np.zeros((3, 3)), np.array([[0, 1, 5]])), "out of range"),
    (lambda: mpumesh.read_volume("/nonexistent/scan.nii.gz"), "/nonexistent/scan.nii.gz"),
    (lambda: mpumesh.write_mesh("/nonexistent/dir/m.ply", {"vertices": np.zeros((3, 3)), "faces": [[0, 1, 2]]}),
     "/nonexistent/dir"),
])
def test_bad_input_raises_value_error_with_the_commands_message(call, words):
    with pytest.raises(ValueError, match=None) as e:
        call()
    assert words in str(e.value), str(e.value)


def test_a_failed_stage_raises_runtime_error(monkeypatch):
    # No Vulkan driver: the GPU backend asked for cannot start.
    monkeypatch.setenv("VK_ICD_FILENAMES", "/nonexistent.json")
    monkeypatch.setenv("VK_DRIVER_FILES", "/nonexistent.json")
    with pytest.raises(RuntimeError):
        mpumesh.run(ball(), spacing=(0.6, 0.6, 2.0), threshold=0, particles=1500, backend="gpu")


def test_a_callback_that_raises_stops_the_run():
    def stop(event, text):
        if text == "fit":
            raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        mpumesh.run(ball(), spacing=(0.6, 0.6, 2.0), threshold=0, particles=1500, backend="cpu", progress=stop)
