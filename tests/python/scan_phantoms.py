"""Small scans for the workflow's tests (tests/python/test_workflow.py, test_slurm.py)."""
import nibabel
import numpy as np


def ball_scan(path, radius, shape=(14, 30, 32), spacing=(0.6, 0.6, 2.0)):
    """A bright ball (1000 HU, 0 outside, a linear edge one voxel wide) as NIfTI."""
    z, y, x = np.meshgrid(*(np.arange(n, dtype=float) for n in shape), indexing="ij")
    p = np.stack([x * spacing[0], y * spacing[1], z * spacing[2]], axis=-1)
    centre = np.array([shape[2] * spacing[0], shape[1] * spacing[1], shape[0] * spacing[2]]) / 2
    d = (radius - np.linalg.norm(p - centre, axis=-1)) / min(spacing)
    data = (500 + 500 * np.clip(d, -1, 1)).astype(np.int16)
    nibabel.save(nibabel.Nifti1Image(np.transpose(data, (2, 1, 0)), np.diag(list(spacing) + [1.0])), path)
