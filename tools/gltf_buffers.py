"""The binary buffer of a glTF file and its buffer views, as the course's asset scripts write
them (tools/make-material-room.py, tools/make-instanced-scene.py): each block added starts at a
multiple of four bytes, as glTF requires of accessor data, and gets a view of its own."""


class BufferViews:
    def __init__(self):
        self.buffer = bytearray()
        self.views = []

    def add(self, data, target):
        """Appends `data` (bytes) for the given target (34962 vertices, 34963 indices) and
        returns the number of its view."""
        while len(self.buffer) % 4:
            self.buffer.append(0)
        self.views.append({"buffer": 0, "byteOffset": len(self.buffer),
                           "byteLength": len(data), "target": target})
        self.buffer.extend(data)
        return len(self.views) - 1
