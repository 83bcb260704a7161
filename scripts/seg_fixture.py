#!/usr/bin/env python3
"""Writes a DICOM Segmentation object (SEG) from a NIfTI-1 label map, as a PACS export or a DICOM
conversion of the segmentation would hold it, so that the SEG reader can be checked against the
label map it was made from.

    python3 scripts/seg_fixture.py public/samples/cardiomesh-spasm-seg.nii.gz OUT.dcm

The NIfTI's world is RAS (its sform); DICOM's is LPS, so x and y change sign, as converters do.
One segment per label (SegmentNumber = the label, SegmentLabel "label N"), one binary frame per
slice and label present (empty ones left out, as SEG writers do), listed last slice first,
explicit VR little endian, the orientation and pixel spacing shared, each frame's position,
segment and TemporalPositionIndex 1 in its own functional groups. Standard library only. The
output is committed (tests read it); rerun only to change it.
"""
import gzip
import struct
import sys

SEG_CLASS = "1.2.840.10008.5.1.4.1.1.66.4"
EXPLICIT_LE = "1.2.840.10008.1.2.1"
INSTANCE = "1.2.826.0.1.3680043.10.1234.37.1"
LONG_VRS = (b"OB", b"OW", b"SQ", b"UN", b"UT", b"UC", b"UR", b"OF", b"OD", b"OL")


def read_nifti(path):
    b = open(path, "rb").read()
    if b[:2] == b"\x1f\x8b":
        b = gzip.decompress(b)
    dims = struct.unpack_from("<8h", b, 40)
    datatype = struct.unpack_from("<h", b, 70)[0]
    offset = int(struct.unpack_from("<f", b, 108)[0])
    rows = [struct.unpack_from("<4f", b, 280 + 16 * r) for r in range(3)]
    ni, nj, nk = dims[1], dims[2], dims[3]
    fmt = {2: "B", 4: "h", 512: "H"}[datatype]
    labels = struct.unpack_from(f"<{ni * nj * nk}{fmt}", b, offset)
    axes = [[rows[r][a] for r in range(3)] for a in range(3)]
    origin = [rows[r][3] for r in range(3)]
    return (ni, nj, nk), origin, axes, labels


def lps(v):
    return [-v[0], -v[1], v[2]]


def norm(v):
    return sum(x * x for x in v) ** 0.5


def ds(values):
    return "\\".join(f"{v:.6f}".rstrip("0").rstrip(".") for v in values)


def element(group, elem, vr, value):
    if isinstance(value, str):
        value = value.encode("ascii")
        if len(value) % 2:
            value += b"\0" if vr == b"UI" else b" "
    elif len(value) % 2:
        value += b"\0"
    head = struct.pack("<HH", group, elem) + vr
    if vr in LONG_VRS:
        return head + b"\0\0" + struct.pack("<I", len(value)) + value
    return head + struct.pack("<H", len(value)) + value


def sequence(group, elem, items):
    body = b""
    for item in items:
        body += struct.pack("<HHI", 0xFFFE, 0xE000, 0xFFFFFFFF) + item
        body += struct.pack("<HHI", 0xFFFE, 0xE00D, 0)
    body += struct.pack("<HHI", 0xFFFE, 0xE0DD, 0)
    return struct.pack("<HH", group, elem) + b"SQ\0\0" + struct.pack("<I", 0xFFFFFFFF) + body


def us(v):
    return struct.pack("<H", v)


def main(src, out):
    (ni, nj, nk), origin, axes, labels = read_nifti(src)
    row = lps(axes[0])
    col = lps(axes[1])
    step = lps(axes[2])
    start = lps(origin)
    frames = []
    bits = []
    present = sorted({l for l in labels if l})
    for k in reversed(range(nk)):
        plane = labels[ni * nj * k: ni * nj * (k + 1)]
        for label in sorted({l for l in plane if l}):
            position = [start[a] + step[a] * k for a in range(3)]
            frames.append(
                sequence(0x0020, 0x9111, [element(0x0020, 0x9128, b"UL", struct.pack("<I", 1))])
                + sequence(0x0020, 0x9113, [element(0x0020, 0x0032, b"DS", ds(position))])
                + sequence(0x0062, 0x000A, [element(0x0062, 0x000B, b"US", us(label))])
            )
            bits.extend(1 if l == label else 0 for l in plane)
    packed = bytearray((len(bits) + 7) // 8)
    for n, bit in enumerate(bits):
        if bit:
            packed[n // 8] |= 1 << (n % 8)
    unit = [v / norm(row) for v in row] + [v / norm(col) for v in col]
    segments = [
        element(0x0062, 0x0004, b"US", us(l)) + element(0x0062, 0x0005, b"LO", f"label {l}")
        for l in present
    ]
    shared = sequence(0x0020, 0x9116, [element(0x0020, 0x0037, b"DS", ds(unit))]) + sequence(
        0x0028,
        0x9110,
        [element(0x0018, 0x0050, b"DS", ds([norm(step)])) + element(0x0028, 0x0030, b"DS", ds([norm(col), norm(row)]))],
    )
    body = (
        element(0x0008, 0x0016, b"UI", SEG_CLASS)
        + element(0x0008, 0x0018, b"UI", INSTANCE)
        + element(0x0008, 0x0060, b"CS", "SEG")
        + element(0x0008, 0x0070, b"LO", "heartmesh test fixture")
        + element(0x0028, 0x0002, b"US", us(1))
        + element(0x0028, 0x0004, b"CS", "MONOCHROME2")
        + element(0x0028, 0x0008, b"IS", str(len(frames)))
        + element(0x0028, 0x0010, b"US", us(nj))
        + element(0x0028, 0x0011, b"US", us(ni))
        + element(0x0028, 0x0100, b"US", us(1))
        + element(0x0028, 0x0101, b"US", us(1))
        + element(0x0028, 0x0102, b"US", us(0))
        + element(0x0062, 0x0001, b"CS", "BINARY")
        + sequence(0x0062, 0x0002, segments)
        + sequence(0x5200, 0x9229, [shared])
        + sequence(0x5200, 0x9230, frames)
        + element(0x7FE0, 0x0010, b"OB", bytes(packed))
    )
    meta = (
        element(0x0002, 0x0001, b"OB", b"\0\1")
        + element(0x0002, 0x0002, b"UI", SEG_CLASS)
        + element(0x0002, 0x0003, b"UI", INSTANCE)
        + element(0x0002, 0x0010, b"UI", EXPLICIT_LE)
        + element(0x0002, 0x0012, b"UI", "1.2.826.0.1.3680043.10.1234.37")
    )
    group_length = element(0x0002, 0x0000, b"UL", struct.pack("<I", len(meta)))
    with open(out, "wb") as f:
        f.write(b"\0" * 128 + b"DICM" + group_length + meta + body)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
