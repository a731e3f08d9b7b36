"""What lumar's asset generators (scripts/make-*.py) share: a glTF binary buffer built view
by view, the GLB container, and an uncompressed-filter RGB PNG. Standard library only; the
output is deterministic, so a regenerated asset is byte-identical."""
import json
import struct
import zlib


class GlbBuffer:
    """The GLB's binary chunk and its bufferViews, each view 4-byte aligned."""

    def __init__(self):
        self.binary = bytearray()
        self.views = []

    def add_view(self, data, target=None):
        """Appends `data` as a bufferView (with `target` where given); returns its index."""
        self.pad()
        view = {"buffer": 0, "byteOffset": len(self.binary), "byteLength": len(data)}
        if target:
            view["target"] = target
        self.binary.extend(data)
        self.views.append(view)
        return len(self.views) - 1

    def pad(self):
        """Pads the binary to 4 bytes (GLB's chunk alignment); returns its length."""
        while len(self.binary) % 4:
            self.binary.append(0)
        return len(self.binary)


def pack_glb(document, buffer):
    """The GLB file of the glTF JSON `document` and the (padded) binary of `buffer`."""
    binary = bytes(buffer.binary)
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    return (struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary)) +
            struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary)


def png_rgb(width, height, rows):
    """An 8-bit RGB PNG of `rows` (one bytes object of width * 3 per row, top first)."""
    raw = b"".join(b"\x00" + bytes(row) for row in rows)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
