"""MyPaint's brush engine (libmypaint 1.6, Debian libmypaint-1.5-1) on a fixed-size canvas.

The GObject bindings (gir1.2-mypaint-1.5, namespace MyPaint 1.6) can load brushes and
paint, but cannot hand back the canvas's pixels (a tile's buffer is a bare pointer), so
this module calls the same library through ctypes: a brush preset (.myb) painting on a
MyPaintFixedTiledSurface, whose tiles are read and written as numpy arrays.

Pixels are MyPaint's: premultiplied RGBA, 1.0 = 1 << 15, in the display (sRGB) encoding
MyPaint blends in.
"""

import ctypes as C

import numpy as np

_lib = C.CDLL("libmypaint-1.5.so.1")
TILE = 64
ONE = float(1 << 15)


class _TileRequest(C.Structure):
    _fields_ = [("tx", C.c_int), ("ty", C.c_int), ("readonly", C.c_int),
                ("buffer", C.POINTER(C.c_uint16)), ("context", C.c_void_p),
                ("thread_id", C.c_int), ("mipmap_level", C.c_int)]


class _Rectangle(C.Structure):
    _fields_ = [("x", C.c_int), ("y", C.c_int), ("width", C.c_int), ("height", C.c_int)]


def _sig(name, res, *args):
    f = getattr(_lib, name)
    f.restype, f.argtypes = res, list(args)


P = C.c_void_p
_sig("mypaint_fixed_tiled_surface_new", P, C.c_int, C.c_int)
_sig("mypaint_fixed_tiled_surface_interface", P, P)
_sig("mypaint_surface_unref", None, P)
_sig("mypaint_surface_begin_atomic", None, P)
_sig("mypaint_surface_end_atomic", None, P, C.POINTER(_Rectangle))
_sig("mypaint_tile_request_init", None, C.POINTER(_TileRequest), C.c_int, C.c_int, C.c_int, C.c_int)
_sig("mypaint_tiled_surface_tile_request_start", None, P, C.POINTER(_TileRequest))
_sig("mypaint_tiled_surface_tile_request_end", None, P, C.POINTER(_TileRequest))
_sig("mypaint_brush_new", P)
_sig("mypaint_brush_unref", None, P)
_sig("mypaint_brush_from_string", C.c_int, P, C.c_char_p)
_sig("mypaint_brush_setting_from_cname", C.c_int, C.c_char_p)
_sig("mypaint_brush_get_base_value", C.c_float, P, C.c_int)
_sig("mypaint_brush_set_base_value", None, P, C.c_int, C.c_float)
_sig("mypaint_brush_reset", None, P)
_sig("mypaint_brush_new_stroke", None, P)
_sig("mypaint_brush_stroke_to", C.c_int, P, P, C.c_float, C.c_float, C.c_float, C.c_float, C.c_float, C.c_double)


class Canvas:
    """A width x height MyPaint surface, started from `ground` (H x W x 4 premultiplied
    RGBA in [0, 1]; libmypaint leaves a new surface's memory uninitialized)."""

    def __init__(self, ground):
        self.height, self.width = ground.shape[:2]
        self._fixed = _lib.mypaint_fixed_tiled_surface_new(self.width, self.height)
        self.surface = _lib.mypaint_fixed_tiled_surface_interface(self._fixed)
        self._tiles(ground, readonly=False)

    def _tiles(self, image, readonly):
        """Copies every tile into `image` (readonly) or `image` into every tile."""
        h, w = self.height, self.width
        for ty in range((h + TILE - 1) // TILE):
            for tx in range((w + TILE - 1) // TILE):
                req = _TileRequest()
                _lib.mypaint_tile_request_init(C.byref(req), 0, tx, ty, int(readonly))
                _lib.mypaint_tiled_surface_tile_request_start(self._fixed, C.byref(req))
                buf = np.ctypeslib.as_array(req.buffer, shape=(TILE, TILE, 4))
                y0, x0 = ty * TILE, tx * TILE
                y1, x1 = min(y0 + TILE, h), min(x0 + TILE, w)
                region = image[y0:y1, x0:x1]
                if readonly:
                    region[...] = buf[: y1 - y0, : x1 - x0] / ONE
                else:
                    tile = np.zeros((TILE, TILE, 4), np.uint16)
                    tile[: y1 - y0, : x1 - x0] = np.round(np.clip(region, 0, 1) * ONE)
                    buf[...] = tile
                _lib.mypaint_tiled_surface_tile_request_end(self._fixed, C.byref(req))

    def pixels(self):
        """The canvas as H x W x 4 premultiplied RGBA floats."""
        out = np.zeros((self.height, self.width, 4))
        self._tiles(out, readonly=True)
        return out

    def __del__(self):
        _lib.mypaint_surface_unref(self.surface)


class Brush:
    """A brush preset (the text of a .myb file)."""

    def __init__(self, myb_text):
        self._b = _lib.mypaint_brush_new()
        if not _lib.mypaint_brush_from_string(self._b, myb_text.encode()):
            raise ValueError("libmypaint could not read the brush")

    def _id(self, name):
        return _lib.mypaint_brush_setting_from_cname(name.encode())

    def get(self, name):
        return _lib.mypaint_brush_get_base_value(self._b, self._id(name))

    def set(self, name, value):
        _lib.mypaint_brush_set_base_value(self._b, self._id(name), float(value))

    def stroke(self, canvas, events):
        """One stroke: `events` are (x, y, pressure, dtime) as a tablet reports them. The
        brush's state (smudge buckets, tracking) starts afresh, as after a pen lift."""
        _lib.mypaint_brush_reset(self._b)
        _lib.mypaint_brush_new_stroke(self._b)
        _lib.mypaint_surface_begin_atomic(canvas.surface)
        for x, y, p, dt in events:
            _lib.mypaint_brush_stroke_to(self._b, canvas.surface, x, y, p, 0.0, 0.0, dt)
        roi = _Rectangle()
        _lib.mypaint_surface_end_atomic(canvas.surface, C.byref(roi))

    def __del__(self):
        _lib.mypaint_brush_unref(self._b)
