#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpus into tests/fuzz/corpus/<target>/ (committed; rerun after a format change).

scenario/ and shape/: the repository's scenarios/*.yaml and shapes/*.txt as they were (the other files there,
written by hand, are left alone: fields the scenarios do not use, and inputs that must be refused). message/ and readings/: inputs encoded by hand after the layouts
documented in robot_agent/controller/message.hpp, motion_section.hpp and common/dds/readings_blob.hpp. An
input that showed a bug (a crash, or a bad input accepted) goes into corpus/<target>/ as well, named
bug-<what>, with a regression test beside the parser's tests.
"""
import pathlib
import shutil
import struct

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
CORPUS = HERE / "corpus"


def motion_section(leader, parent, net_force, vx, vy, strain):
    return struct.pack("<BBi4f", 1, 1 if leader else 0, parent, net_force, vx, vy, strain)


def message(sender, state, label, pose, origin=None, free=(), entries=(), motion=b"", digest=0):
    out = struct.pack("<BBIBh3fB2fIfBQ", 0x53, 3, sender, state, label, *pose, 1 if origin else 0,
                      *(origin or (0.0, 0.0)), sender, 1.5, 0, digest)
    out += struct.pack("<B", len(free)) + b"".join(struct.pack("<h", f) for f in free)
    out += struct.pack("<B", len(entries)) + b"".join(struct.pack("<IqII", *e) for e in entries)
    return out + struct.pack("<H", len(motion)) + motion


def readings(items):
    out = struct.pack("<I", len(items))
    for sender, rng, bearing, data in items:
        out += struct.pack("<IddI", sender, rng, bearing, len(data)) + data
    return out


def write(target, name, data):
    folder = CORPUS / target
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_bytes(data)


def main():
    for target, pattern, folder in (("scenario", "*.yaml", "scenarios"), ("shape", "*.txt", "shapes")):
        (CORPUS / target).mkdir(parents=True, exist_ok=True)
        for f in sorted((ROOT / folder).glob(pattern)):
            shutil.copyfile(f, CORPUS / target / f.name)

    ms = motion_section(True, -1, 0.25, 0.1, -0.2, 0.0)
    write("message", "idle.bin", message(0, 0, -1, (0.0, 0.0, 0.0)))
    write("message", "labelled.bin", message(3, 2, 4, (1.5, -2.25, 0.75), origin=(0.5, 0.5), free=(1, 5, 7)))
    write("message", "entries.bin", message(7, 3, 0, (4.0, 1.0, -3.0), origin=(0.0, 0.0), free=(2,),
                                            entries=((1, -5, 2, 7), (0x10002, 1 << 40, 9, 3)), digest=0x1234))
    write("message", "motion.bin", message(2, 4, 1, (0.0, 3.0, 1.5), origin=(1.0, 1.0), motion=ms, digest=7))
    write("readings", "empty.bin", readings([]))
    write("readings", "one.bin", readings([(1, 0.8, 0.3, message(1, 1, -1, (0.0, 0.0, 0.0)))]))
    write("readings", "three.bin", readings([(0, 1.0, -1.0, b""), (4, 2.5, 3.1, b"\x53\x03abc"),
                                             (9, 0.3, 0.0, message(9, 4, 2, (1.0, 2.0, 3.0), motion=ms))]))


if __name__ == "__main__":
    main()
