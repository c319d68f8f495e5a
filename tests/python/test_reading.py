"""Reading files from Python cannot take the interpreter down: every DICOM file of
pydicom's test corpus (Debian's python3-pydicom) through mpumesh.read_volume either reads
or raises ValueError naming the file, within its time limit; a crash or a hang of the
reader's child process (core/io/isolated_read.h, forced by MPUMESH_READER_TEST) is a
ValueError too, and the interpreter goes on.

Run by ctest (tests/CMakeLists.txt) with PYTHONPATH at the built module."""
import glob
import os
import time

import numpy as np
import pytest

import mpumesh

CORPUS = "/usr/lib/python3/dist-packages/pydicom/data/test_files"
FILES = sorted(glob.glob(os.path.join(CORPUS, "*.dcm")))


def test_the_corpus_is_there():
    assert len(FILES) >= 60, "install python3-pydicom"


@pytest.mark.parametrize("path", FILES, ids=os.path.basename)
def test_every_corpus_file_reads_or_raises_value_error(path, monkeypatch):
    monkeypatch.setenv("MPUMESH_READER_TIMEOUT", "60")
    t0 = time.monotonic()
    try:
        vol, spacing, origin, direction = mpumesh.read_volume(path)
        assert vol.ndim == 3 and np.isfinite(vol).all()
        assert len(spacing) == 3 and all(s > 0 for s in spacing)
    except ValueError as e:
        assert str(e).startswith(path + ": "), str(e)
        assert "\n" not in str(e)
    assert time.monotonic() - t0 < 60


@pytest.mark.parametrize("name, words", [
    ("rtdose_1frame.dcm", "the DICOM reader crashed (abort)"),
    ("rtplan.dcm", "holds no image to mesh: it is an RT plan"),
    ("waveform_ecg.dcm", "holds no image to mesh: it is a waveform"),
])
def test_what_a_file_is_and_how_its_reader_failed(name, words):
    with pytest.raises(ValueError) as e:
        mpumesh.read_volume(os.path.join(CORPUS, name))
    assert words in str(e.value), str(e.value)


def test_a_crash_or_a_hang_of_the_readers_child_is_a_value_error(monkeypatch):
    ok = os.path.join(CORPUS, "CT_small.dcm")
    monkeypatch.setenv("MPUMESH_READER_TEST", "abort")
    with pytest.raises(ValueError, match="the DICOM reader crashed \\(abort\\)"):
        mpumesh.read_volume(ok)
    monkeypatch.setenv("MPUMESH_READER_TEST", "hang")
    monkeypatch.setenv("MPUMESH_READER_TIMEOUT", "1")
    t0 = time.monotonic()
    with pytest.raises(ValueError, match="ran past its time limit of 1 s"):
        mpumesh.read_volume(ok)
    assert time.monotonic() - t0 < 10
    monkeypatch.delenv("MPUMESH_READER_TEST")
    vol, *_ = mpumesh.read_volume(ok)  # and the interpreter reads on
    assert vol.shape == (1, 128, 128)
