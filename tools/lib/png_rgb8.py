"""A minimal 8-bit RGB PNG encoder (zlib only), shared by tools/make_scenes.py and
tests/fuzz/make_seeds.py so that scenes and fuzz seeds carry byte-identical texture images
without depending on an imaging library."""
import struct
import zlib


def png_rgb8(width, height, rows):
    """PNG bytes of rows: a list of `height` lists of `width` (r, g, b) tuples of 0..255."""
    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xffffffff)
    raw = b"".join(b"\x00" + bytes(c for px in row for c in px) for row in rows)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
