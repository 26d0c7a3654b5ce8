#!/usr/bin/env python3
"""Writes the binary files of corpus/ (gzip data, NUL bytes), which an editor cannot make.

The text files of the corpus are written by hand; these are made by this script so that
anyone can see, and remake, exactly what each one holds. The gzip files keep their one-line
comment inside the compressed text (`zcat FILE | head -1` shows it).

    tests/05_obj_loading/make_binary_corpus.py
"""
import gzip
import pathlib

CORPUS = pathlib.Path(__file__).resolve().parent / "corpus"
TRIANGLE = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"


def gz(text):
    # mtime=0: the same bytes on every run
    return gzip.compress(text, compresslevel=9, mtime=0)


def write(name, data):
    (CORPUS / name).write_bytes(data)


def main():
    write("bad_binary_garbage.obj",
          b"# attacks: binary data with NUL bytes in it, from the next line on\n" +
          bytes(range(256)) * 2)
    write("bad_binary_high_bytes.obj",
          b"# attacks: binary data without NUL bytes (a loader that skips unknown lines "
          b"would skip it all)\n" + bytes(range(0x80, 0x100)) * 2)

    comment = b"# attacks (gzip): %s\n"
    text = comment % b"gzip data cut off before its end" + TRIANGLE * 50
    packed = gz(text)
    write("bad_truncated.obj.gz", packed[: len(packed) // 2])

    text = comment % b"gzip data with damaged compressed bytes"
    packed = bytearray(gz(text + TRIANGLE * 50))
    for i in range(len(packed) // 2, len(packed) // 2 + 8):
        packed[i] ^= 0x5A
    write("bad_corrupt.obj.gz", bytes(packed))

    text = comment % b"gzip data whose checksum does not match what it unpacks to"
    packed = bytearray(gz(text + TRIANGLE))
    packed[-8] ^= 0xFF  # first byte of the CRC-32 in the gzip trailer
    write("bad_crc.obj.gz", bytes(packed))

    text = comment % b"bytes after the end of the gzip data"
    write("bad_trailing_bytes.obj.gz", gz(text + TRIANGLE) + b"not gzip")

    text = comment % b"an error inside gzip data must still name its line"
    write("bad_gzip_inner_error.obj.gz", gz(text + b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"))

    # Two gzip members one after another, as `cat a.gz b.gz` makes: one valid file.
    first = b"# two gzip members: the vertices in one, the face in the other\n" + TRIANGLE[:-8]
    write("good_two_members.obj.gz", gz(first) + gz(TRIANGLE[-8:]))


if __name__ == "__main__":
    main()
