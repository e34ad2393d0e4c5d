#!/usr/bin/env python3
"""Write an AMBW v1 wear record (firmware/wear/wear_record.hpp) with Python's struct and
zlib.crc32 only: an encoder written independently of the C++ one, so the target test also
checks that the board accepts the format as documented.

usage: make_wear_record.py OUT BOARD_NAME SEQUENCE [EVENT_COUNT]
"""
import math
import struct
import sys
import time
import zlib

LOAD_BINS = 360


def encode(board, sequence, event_count):
    out = bytearray()
    out += struct.pack("<IHHI", 0x57424D41, 1, 0, sequence)
    out += board.encode()[:31].ljust(32, b"\0")
    out += b"target-test-linear".ljust(64, b"\0")
    out += struct.pack("<Ifq", event_count, 0.14, int(time.time()))
    for bearing in range(2):
        # A load concentrated towards the bottom of the ring (180 deg), like a drop.
        event = [max(0.0, 900.0 * math.cos(math.radians(i - 180))) for i in range(LOAD_BINS)]
        cumulative = [v * event_count for v in event]
        out += struct.pack("<%df" % LOAD_BINS, *event)
        out += struct.pack("<%df" % LOAD_BINS, *cumulative)
        # swing, forward rub, backward rub (s), friction energy (J), peak force (N), life used
        out += struct.pack("<6f", 0.05, 0.4, 0.0, 12.5 + bearing, 2400.0 + 100 * bearing, 0.0125 * sequence)
    out += struct.pack("<I", zlib.crc32(bytes(out)) & 0xFFFFFFFF)
    return bytes(out)


if __name__ == "__main__":
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    data = encode(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]) if len(sys.argv) > 4 else 1)
    with open(sys.argv[1], "wb") as f:
        f.write(data)
    print("%s: %d bytes, sequence %s" % (sys.argv[1], len(data), sys.argv[3]))
