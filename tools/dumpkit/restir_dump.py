#!/usr/bin/env python3
"""Reader and writer of the restir stage-dump formats (docs/formats.md), standard library only.

    .resv   reservoir dump, version 1 (64-byte header, 216- or 576-byte records)
    .gbuf   G-buffer dump, version 1 (32-byte header, 108-byte records)
    manifest.json of a --dump-dir directory

Written from docs/formats.md, not from the C code, so that it checks the spec as much as the
files: a GPU build can write its dumps with write_resv()/write_gbuf() and diff them with
`restir diff-dump`. Records are dicts keyed by the field names of docs/formats.md "Record".

Usage as a tool:
    restir_dump.py show FILE.resv [N]      header and the first N records (default 3)
    restir_dump.py check DIR               every file the manifest names is present and readable
    restir_dump.py roundtrip FILE OUT      read and write back (OUT must be byte-identical)
    restir_dump.py selftest DIR            check DIR, and read and write back every file of it
                                           in memory: exit 1 if one does not give its bytes back
"""
import json
import math
import os
import struct
import sys

RESV_MAGIC = b"RSTRRESV"
GBUF_MAGIC = b"RSTRGBUF"
RESV_HEADER = struct.Struct("<8sIIIIIIIIQ16s")  # 64 bytes
GBUF_HEADER = struct.Struct("<8sIIIIII")  # 32 bytes
FLAG_PSS = 1
MAX_PSS = 45
LOBES = 16
# Record bytes 0..215 (docs/formats.md "Record"), little-endian, no padding.
RECORD = struct.Struct("<dddII" "III" "BBBB" "16s" "I" "2f" "3f" "3f" "I" "3d" "ddd" "3d" "d" "3d" "d")
GBUF_RECORD = struct.Struct("<IIII" "3f" "3f" "3f" "3f" "3f" "f" "f" "f" "2f" "2f" "I")
assert RESV_HEADER.size == 64 and RECORD.size == 216 and GBUF_HEADER.size == 32 and GBUF_RECORD.size == 108

RECORD_FIELDS = ["wsum", "W", "confidence", "n_invalid", "reserved", "seed", "pixel", "sample", "length",
                 "technique", "rc_k", "n_pss", "lobe", "rc_triangle", "rc_bary", "rc_position", "rc_normal",
                 "rc_flags", "rc_wo", "rc_pdf_prev", "rc_geom", "rc_pdf", "rc_radiance", "light_pdf", "F", "target"]
# how many struct items each field takes
_WIDTH = {"rc_bary": 2, "rc_position": 3, "rc_normal": 3, "rc_wo": 3, "rc_radiance": 3, "F": 3}
GBUF_FIELDS = ["valid", "triangle", "material", "object", "bary_t", "position", "ng", "ns", "view_dir", "distance",
               "cos_theta", "depth", "pixel", "motion", "prev_valid"]
_GBUF_WIDTH = {"bary_t": 3, "position": 3, "ng": 3, "ns": 3, "view_dir": 3, "pixel": 2, "motion": 2}


class DumpError(Exception):
    """A file that does not follow docs/formats.md: 'file: what is wrong'."""


def _split(values, names, widths):
    out, i = {}, 0
    for name in names:
        w = widths.get(name, 1)
        out[name] = list(values[i:i + w]) if w > 1 else values[i]
        i += w
    return out


def _join(rec, names, widths):
    values = []
    for name in names:
        v = rec[name]
        values.extend(v if widths.get(name, 1) > 1 else [v])
    return values


def empty_record():
    """The contents of an empty reservoir's record as the oracle writes it (docs/formats.md
    "Empty records"): every number 0 (confidence and n_invalid may be set), lobes 0xFF."""
    rec = {name: 0 for name in RECORD_FIELDS}
    for name, w in _WIDTH.items():
        rec[name] = [0.0] * w
    rec["lobe"] = bytes([0xFF] * LOBES)
    rec["wsum"] = rec["W"] = rec["confidence"] = 0.0
    rec["pss"] = [0.0] * MAX_PSS
    return rec


def decode_record(buf, flags):
    rec = _split(RECORD.unpack_from(buf, 0), RECORD_FIELDS, _WIDTH)
    rec["pss"] = list(struct.unpack_from("<45d", buf, 216)) if flags & FLAG_PSS else [0.0] * MAX_PSS
    return rec


def encode_record(rec, flags):
    buf = RECORD.pack(*_join(rec, RECORD_FIELDS, _WIDTH))
    if flags & FLAG_PSS:
        pss = list(rec.get("pss", [])) + [0.0] * MAX_PSS
        buf += struct.pack("<45d", *pss[:MAX_PSS])
    return buf


def read_resv(path):
    """(header dict, list of record dicts). Checks what docs/formats.md "What the reader checks" lists."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 64:
        raise DumpError("%s: shorter than the 64-byte header" % path)
    magic, version, hsize, rsize, flags, width, height, frame, real_bits, count, tag = RESV_HEADER.unpack_from(data)
    if magic != RESV_MAGIC:
        raise DumpError("%s: not a reservoir dump (magic)" % path)
    if version != 1 or hsize != 64 or flags & ~FLAG_PSS or rsize != (216 + 8 * MAX_PSS if flags & FLAG_PSS else 216):
        raise DumpError("%s: version %d, header %d, record %d, flags %#x not supported" % (path, version, hsize, rsize, flags))
    if real_bits not in (32, 64) or width == 0 or height == 0 or count != width * height or count > 1 << 26:
        raise DumpError("%s: bad real_bits, size or count" % path)
    if len(data) != 64 + count * rsize:
        raise DumpError("%s: %d bytes, the header implies %d" % (path, len(data), 64 + count * rsize))
    tag_text = tag.rstrip(b"\0")
    if any(c < 0x20 or c > 0x7E for c in tag_text):
        raise DumpError("%s: tag is not printable ASCII" % path)
    header = {"flags": flags, "width": width, "height": height, "frame": frame, "real_bits": real_bits,
              "tag": tag_text.decode("ascii")}
    records = []
    for i in range(count):
        rec = decode_record(data[64 + i * rsize:64 + (i + 1) * rsize], flags)
        for name in ("wsum", "W", "confidence"):
            if not rec[name] >= 0:  # NaN fails too
                raise DumpError("%s: record %d: %s = %r" % (path, i, name, rec[name]))
        records.append(rec)
    return header, records


def write_resv(path, header, records):
    """Writes atomically (a temporary file renamed into place). The PSS flag is set exactly when
    some record has n_pss > 0, as the oracle's writer does."""
    width, height = header["width"], header["height"]
    if len(records) != width * height:
        raise DumpError("%s: %d records for %dx%d" % (path, len(records), width, height))
    flags = FLAG_PSS if any(r["n_pss"] > 0 for r in records) else 0
    tag = header["tag"].encode("ascii")
    if len(tag) > 16:
        raise DumpError("%s: tag longer than 16 bytes" % path)
    head = RESV_HEADER.pack(RESV_MAGIC, 1, 64, 216 + (8 * MAX_PSS if flags else 0), flags, width, height,
                            header.get("frame", 0), header.get("real_bits", 64), width * height, tag.ljust(16, b"\0"))
    _atomic_write(path, head + b"".join(encode_record(r, flags) for r in records))


def read_gbuf(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 32:
        raise DumpError("%s: shorter than the 32-byte header" % path)
    magic, version, hsize, rsize, width, height, frame = GBUF_HEADER.unpack_from(data)
    if magic != GBUF_MAGIC or version != 1 or hsize != 32 or rsize != 108:
        raise DumpError("%s: not a version-1 G-buffer dump" % path)
    if len(data) != 32 + 108 * width * height:
        raise DumpError("%s: %d bytes, the header implies %d" % (path, len(data), 32 + 108 * width * height))
    texels = [_split(GBUF_RECORD.unpack_from(data, 32 + 108 * i), GBUF_FIELDS, _GBUF_WIDTH)
              for i in range(width * height)]
    return {"width": width, "height": height, "frame": frame}, texels


def write_gbuf(path, header, texels):
    head = GBUF_HEADER.pack(GBUF_MAGIC, 1, 32, 108, header["width"], header["height"], header.get("frame", 0))
    _atomic_write(path, head + b"".join(GBUF_RECORD.pack(*_join(t, GBUF_FIELDS, _GBUF_WIDTH)) for t in texels))


def read_manifest(directory):
    with open(os.path.join(directory, "manifest.json")) as f:
        m = json.load(f)
    if m.get("format") != "restir-stage-dump":
        raise DumpError("%s/manifest.json: \"format\" must be \"restir-stage-dump\"" % directory)
    for key in ("frames", "stage_order"):
        if key not in m:
            raise DumpError("%s/manifest.json: missing \"%s\"" % (directory, key))
    return m


SCHEMA_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "dump-manifest.schema.json")
_TYPES = {"object": dict, "array": list, "string": str, "boolean": bool, "null": type(None)}


def _is_type(value, name):
    if name == "integer":
        return isinstance(value, int) and not isinstance(value, bool)
    if name == "number":
        return isinstance(value, (int, float)) and not isinstance(value, bool)
    return isinstance(value, _TYPES[name])


def validate(value, schema, where="manifest"):
    """The subset of JSON Schema docs/dump-manifest.schema.json uses (type, required,
    properties, items, enum, const, minimum); raises DumpError naming the first violation."""
    types = schema.get("type")
    if types is not None and not any(_is_type(value, t) for t in (types if isinstance(types, list) else [types])):
        raise DumpError("%s: %r is not of type %s" % (where, value, types))
    if "const" in schema and value != schema["const"]:
        raise DumpError("%s: %r is not %r" % (where, value, schema["const"]))
    if "enum" in schema and value not in schema["enum"]:
        raise DumpError("%s: %r is not one of %r" % (where, value, schema["enum"]))
    if "minimum" in schema and _is_type(value, "number") and value < schema["minimum"]:
        raise DumpError("%s: %r < %r" % (where, value, schema["minimum"]))
    if isinstance(value, dict):
        for key in schema.get("required", []):
            if key not in value:
                raise DumpError("%s: missing \"%s\"" % (where, key))
        for key, sub in schema.get("properties", {}).items():
            if key in value:
                validate(value[key], sub, "%s.%s" % (where, key))
    if isinstance(value, list) and "items" in schema:
        for i, item in enumerate(value):
            validate(item, schema["items"], "%s[%d]" % (where, i))


def validate_manifest(manifest, schema_path=SCHEMA_PATH):
    """Validates against docs/dump-manifest.schema.json when the kit sits in its repository."""
    if os.path.exists(schema_path):
        with open(schema_path) as f:
            validate(manifest, json.load(f))
        return True
    return False


def stage_path(directory, frame, stage, ext="resv"):
    return os.path.join(directory, "frame_%04d" % frame, "%s.%s" % (stage, ext))


def _atomic_write(path, data):
    tmp = path + ".tmp%d" % os.getpid()
    with open(tmp, "wb") as f:
        f.write(data)
    os.replace(tmp, path)


def check_dir(directory):
    """Every dumped stage of every written frame is present and readable; returns the file count."""
    m = read_manifest(directory)
    validate_manifest(m)
    frames = m["frames"]
    last = frames["first"] + frames.get("written", frames["last"] - frames["first"] + 1) - 1
    region = m.get("region")
    width = region["width"] if region else m["image"]["width"]
    height = region["height"] if region else m["image"]["height"]
    n = 0
    for frame in range(frames["first"], last + 1):
        for stage in m.get("dumped_stages", m["stage_order"]):
            header, _ = read_resv(stage_path(directory, frame, stage))
            if (header["frame"], header["tag"], header["width"], header["height"]) != (frame, stage, width, height):
                raise DumpError("%s: frame %d stage %s %dx%d" % (stage_path(directory, frame, stage), header["frame"],
                                                                header["tag"], header["width"], header["height"]))
            n += 1
    return n


def selftest(directory):
    """check_dir, then every .resv/.gbuf file decoded and encoded again must give its own bytes."""
    import glob
    import tempfile
    n = check_dir(directory)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "rt")
        for path in sorted(glob.glob(os.path.join(directory, "frame_*", "*.*"))):
            if path.endswith(".gbuf"):
                write_gbuf(out, *read_gbuf(path))
            elif path.endswith(".resv"):
                write_resv(out, *read_resv(path))
            else:
                continue
            with open(path, "rb") as a, open(out, "rb") as b:
                if a.read() != b.read():
                    raise DumpError("%s: written back with other bytes" % path)
            n += 1
    return n


def main(argv):
    if len(argv) >= 2 and argv[0] == "show":
        header, records = read_resv(argv[1])
        print(json.dumps(header))
        for rec in records[:int(argv[2]) if len(argv) > 2 else 3]:
            rec = dict(rec, lobe=list(rec["lobe"]))
            rec["pss"] = rec["pss"][:rec["n_pss"]]
            print(json.dumps(rec))
        return 0
    if len(argv) == 2 and argv[0] == "check":
        print("%d stage files ok" % check_dir(argv[1]))
        return 0
    if len(argv) == 2 and argv[0] == "selftest":
        print("%d checks ok" % selftest(argv[1]))
        return 0
    if len(argv) == 3 and argv[0] == "roundtrip":
        if argv[1].endswith(".gbuf"):
            write_gbuf(argv[2], *read_gbuf(argv[1]))
        else:
            write_resv(argv[2], *read_resv(argv[1]))
        return 0
    sys.stderr.write(__doc__)
    return 2


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except (DumpError, OSError, ValueError, KeyError) as exc:
        sys.stderr.write("restir_dump.py: %s\n" % exc)
        sys.exit(2)
