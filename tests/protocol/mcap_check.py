#!/usr/bin/env python3
"""Independent check of an MCAP file written by bop::recording::McapWriter.

Parses the file with struct only (spec: https://mcap.dev/spec), walks every record, checks both
magics, the DataEnd CRC (bytes from file start up to DataEnd) and the Footer's summary CRC, and
prints one 'key value' line per fact for TestMcap.cpp to compare. Exit status 1 on any problem.
Usage: mcap_check.py FILE
"""
import struct
import sys
import zlib

MAGIC = b"\x89MCAP0\r\n"


def string(buf, at):
    (n,) = struct.unpack_from("<I", buf, at)
    return buf[at + 4:at + 4 + n].decode("utf-8"), at + 4 + n


def main(path):
    data = open(path, "rb").read()
    if data[:8] != MAGIC or data[-8:] != MAGIC:
        sys.exit("bad magic")
    pos, counts, messages, topics, data_end_pos = 8, {}, 0, [], None
    while True:
        op, length = struct.unpack_from("<BQ", data, pos)
        body = data[pos + 9:pos + 9 + length]
        if len(body) != length:
            sys.exit("record at %d runs past the end" % pos)
        counts[op] = counts.get(op, 0) + 1
        if op == 0x01:
            profile, at = string(body, 0)
            library, _ = string(body, at)
            print("header profile=%r library=%r" % (profile, library))
        elif op == 0x04 and data_end_pos is None:
            topic, _ = string(body, 4)
            topics.append(topic)
        elif op == 0x05:
            messages += 1
        elif op == 0x0F:
            data_end_pos = pos
            (crc,) = struct.unpack("<I", body)
            print("data_crc", "ok" if crc == zlib.crc32(data[:pos]) else "BAD")
        elif op == 0x0B:
            fields = struct.unpack_from("<QHIIIIQQ", body)
            print("statistics messages=%d schemas=%d channels=%d start=%d end=%d" % (
                fields[0], fields[1], fields[2], fields[6], fields[7]))
        elif op == 0x02:
            start, offset_start, crc = struct.unpack("<QQI", body)
            print("summary_crc", "ok" if crc == zlib.crc32(data[start:pos + 9 + 16]) else "BAD")
            if pos + 9 + 20 + 8 != len(data):
                sys.exit("footer is not followed by exactly the closing magic")
            break
        pos += 9 + length
    print("records", " ".join("%d=%d" % kv for kv in sorted(counts.items())))
    print("messages", messages)
    print("topics", ",".join(topics))


if __name__ == "__main__":
    main(sys.argv[1])
