#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz harnesses: OUT/<harness>/<seed> for every harness in tests/fuzz.

Python standard library only; the seeds are small valid files and a few near misses, so the fuzzer starts
inside each format instead of guessing its magic bytes and headers.
Usage: make_corpus.py OUT
"""
import pathlib
import struct
import sys
import zlib


def npy(descr, shape, values, version=1, fortran=False):
    shape_text = "(" + ", ".join(str(n) for n in shape) + ("," if len(shape) == 1 else "") + ")"
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (descr, fortran, shape_text)
    prefix_len = 10 if version == 1 else 12
    total = (prefix_len + len(header) + 1 + 63) // 64 * 64
    header = (header + " " * (total - prefix_len - len(header) - 1) + "\n").encode()
    length = struct.pack("<H", len(header)) if version == 1 else struct.pack("<I", len(header))
    code = "f" if descr.endswith("4") else "d"
    data = struct.pack("<%d%s" % (len(values), code), *values)
    return b"\x93NUMPY" + bytes([version, 0]) + length + header + data


def npy_header(header, data=b"\0" * 96):
    """A .npy whose header dict is `header` as given (near misses of numpy's own)."""
    total = (10 + len(header) + 1 + 63) // 64 * 64
    text = (header + " " * (total - 10 - len(header) - 1) + "\n").encode()
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(text)) + text + data


def png(width, height, colour_type, depth, pixels):
    """A PNG of one IDAT chunk: `pixels` rows of packed samples, each row behind filter byte 0."""
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour_type]
    row = (width * channels * depth + 7) // 8
    raw = b"".join(b"\0" + pixels[y * row:(y + 1) * row] for y in range(height))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header = struct.pack(">IIBBBBB", width, height, depth, colour_type, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


def seeds():
    floats = [0.5 * k for k in range(6)]
    yield "npy", {
        "f4_2x3": npy("<f4", (2, 3), floats),
        "f8_3x2": npy("<f8", (3, 2), floats),
        "f8_v2": npy("<f8", (2, 2), floats[:4], version=2),
        "f4_v3": npy("<f4", (1, 4), floats[:4], version=3),
        "f4_1d": npy("<f4", (4,), floats[:4]),
        "fortran": npy("<f8", (2, 2), floats[:4], fortran=True),
        "nan": npy("<f4", (1, 2), [float("nan"), 1.0]),
        "truncated": npy("<f8", (4, 4), floats),
        "huge_shape": npy("<f8", (2305843009213693951, 1), floats[:1]),
        "empty": npy("<f4", (0, 3), []),
        # Headers numpy refuses: a negative dimension, 'shape' only inside another value, a key twice.
        "negative_rows": npy_header("{'descr': '<f4', 'fortran_order': False, 'shape': (-1, 8), }"),
        "negative_cols": npy_header("{'descr': '<f4', 'fortran_order': False, 'shape': (12, -8), }"),
        "shape_in_string": npy_header("{'descr': '<f4', 'fortran_order': False, 'x': \"'shape': (2, 3)\"}"),
        "nested_shape": npy_header("{'descr': '<f4', 'fortran_order': False, 'm': {'shape': (2, 3)}}"),
        "shape_twice": npy_header("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), 'shape': (4, 4)}"),
    }
    # csv: the first byte chooses the header (index,place / place / a,b,c / i,j,score / x,y)
    yield "csv", {
        "places": b"\x00index,place\n0,0\n1,0\n2,1\n",
        "junctions": b"\x01place\n# comment\n\n3\r\n7\r\n",
        "three": b"\x02a,b,c\n1,2,3\n4,5\n",
        "scores": b"\x03i,j,score\n0,5,0.9\n",
        "wrong_header": b"\x04x,z\n1,2\n",
    }
    yield "odometry_csv", {
        "poses": b"index,x,y,theta\n0,0,0,0\n1,1.5,0,0.1\n2,3,0.2,-3.2\n",
        "increments": b"index,dx,dy,dtheta\n0,0,0,0\n1,1,0,0.5\n2, 1 ,+0.5,1e-3\n",
        "ground_truth": b"index,x,y\n0,0,0\n1,2,3\n",
        "overflow": b"index,dx,dy,dtheta\n0,1e308,0,0\n1,1e308,0,0\n",
        "out_of_order": b"index,x,y,theta\n1,0,0,0\n",
        "not_finite": b"index,x,y\n0,inf,0\n",
    }
    yield "places_csv", {
        "places": b"index,place\n0,0\n1,0\n2,1\n3,2\n",
        "junctions": b"place\n1\n4\n",
        "negative": b"index,place\n0,-1\n",
        "crlf": b"index,place\r\n0,0\r\n1,99999999999\r\n",
    }
    yield "fasta", {
        "two": b">a first\nACGT\nAC GT\n>b\nTTTT\n",
        "crlf": b">x\r\nAC\r\nGT\r\n",
        "empty_record": b">a\n>b\nAC\n",
        "text_first": b"ACGT\n>a\nAC\n",
    }
    yield "strings_file", {
        "plain": b"# id\tstring\np0\tabcab\np1\t\np2\tzz\n",
        "positions": b"p0\tab\t1.5\t-2\np1\tba\t0\t0\tkitchen\r\n",
        "repeated": b"p0\ta\np0\tb\n",
        "bad_number": b"p0\ta\tx\t1\n",
    }
    corridor = pathlib.Path(__file__).resolve().parents[2] / "data" / "rtabmap-corridor"
    yield "png_jpeg", {
        "grey_8": png(4, 3, 0, 8, bytes(range(12))),
        "rgb_8": png(3, 2, 2, 8, bytes(range(18))),
        "rgba_16": png(2, 2, 6, 16, bytes(range(32))),
        "grey_1": png(9, 2, 0, 1, bytes([0b10101010, 0b10000000, 0b01010101, 0b00000000])),
        "truncated": png(4, 3, 0, 8, bytes(range(12)))[:-20],
        "corridor_jpeg": (corridor / "1.jpg").read_bytes(),
        "jpeg_cut": (corridor / "2.jpg").read_bytes()[:400],
    }
    yield "config_file", {
        "yaml": b"---\n# map options\ngap: 1.5\nkappa: 3  # comment\nout: 'my out'\nname: \"q\"\n",
        "json": b'{"gap": 1.5}\n',
        "no_colon": b"gap 1.5\n",
        "no_name": b": 3\n",
        "crlf": b"threads: 2\r\nevery: 1\r\n",
        "hash_in_quotes": b"out: \"run#2\"  # the second\nnote: it's # a comment\nname: 'a#b'\n",
    }


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = pathlib.Path(sys.argv[1])
    count = 0
    for harness, files in seeds():
        folder = out / harness
        folder.mkdir(parents=True, exist_ok=True)
        for name, data in files.items():
            (folder / name).write_bytes(data)
            count += 1
    print(f"make_corpus: {count} seeds in {out}")


if __name__ == "__main__":
    main()
