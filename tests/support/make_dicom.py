#!/usr/bin/python3
"""Writes small CT series with known defects for the bad-input tests (pydicom, no numpy).

usage: make_dicom.py DIR [--slices N] [--size R C] [--spacing MM] [--tilt DEG]
                         [--drop K] [--dup K] [--resize K] [--truncate K]

A ball of 300 HU on -1000 HU, 2 mm slices. --tilt shears the slice positions along y
(gantry tilt), --drop removes slice K (a gap), --dup writes slice K twice, --resize makes
slice K a different size, --truncate cuts slice K's pixel data short.
"""
import argparse
import math
import os
import struct

import pydicom
from pydicom.dataset import Dataset, FileMetaDataset
from pydicom.uid import ExplicitVRLittleEndian, generate_uid

CT_IMAGE = "1.2.840.10008.5.1.4.1.1.2"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("dir")
    ap.add_argument("--slices", type=int, default=12)
    ap.add_argument("--size", type=int, nargs=2, default=[24, 24])
    ap.add_argument("--spacing", type=float, default=2.0)
    ap.add_argument("--tilt", type=float, default=0.0)
    ap.add_argument("--drop", type=int, default=-1)
    ap.add_argument("--dup", type=int, default=-1)
    ap.add_argument("--resize", type=int, default=-1)
    ap.add_argument("--truncate", type=int, default=-1)
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    study, series, frame = generate_uid(), generate_uid(), generate_uid()
    shear = math.tan(math.radians(a.tilt))
    n = 0
    for k in range(a.slices):
        if k == a.drop:
            continue
        for copy in range(2 if k == a.dup else 1):
            rows, cols = a.size
            if k == a.resize:
                rows, cols = rows + 4, cols + 4
            z = k * a.spacing
            pixels = bytearray()
            for r in range(rows):
                for c in range(cols):
                    d = math.sqrt((c - cols / 2) ** 2 + (r - rows / 2) ** 2 + ((z - a.slices) / 1.0) ** 2)
                    pixels += struct.pack("<h", 1300 if d < min(rows, cols) / 3 else 0)
            if k == a.truncate:
                pixels = pixels[: len(pixels) // 3]
            meta = FileMetaDataset()
            meta.MediaStorageSOPClassUID = CT_IMAGE
            meta.MediaStorageSOPInstanceUID = generate_uid()
            meta.TransferSyntaxUID = ExplicitVRLittleEndian
            ds = Dataset()
            ds.file_meta = meta
            ds.is_little_endian, ds.is_implicit_VR = True, False
            ds.SOPClassUID, ds.SOPInstanceUID = CT_IMAGE, meta.MediaStorageSOPInstanceUID
            ds.Modality = "CT"
            ds.PatientName, ds.PatientID = "Phantom^Ball", "0"
            ds.StudyInstanceUID, ds.SeriesInstanceUID, ds.FrameOfReferenceUID = study, series, frame
            ds.SeriesNumber, ds.InstanceNumber = 1, n + 1
            ds.ImagePositionPatient = [0.0, z * shear, z]
            ds.ImageOrientationPatient = [1, 0, 0, 0, 1, 0]
            ds.PixelSpacing = [0.8, 0.8]
            ds.SliceThickness = a.spacing
            ds.Rows, ds.Columns = rows, cols
            ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
            ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
            ds.RescaleIntercept, ds.RescaleSlope = -1000, 1
            ds.PixelData = bytes(pixels)
            ds.save_as(os.path.join(a.dir, "slice%03d.dcm" % n), write_like_original=False)
            n += 1


if __name__ == "__main__":
    main()
