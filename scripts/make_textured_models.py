#!/usr/bin/env python3
"""Writes three textured glTF 2.0 test models for printlight's prepare/optimize.

  box_photo        12 mm cube, each face its own tile of a 3x2 atlas of
                   photograph-like colour noise (skin, foliage, mid-tones)
  cylinder_logo    12 mm x 12 mm cylinder (64 segments), flat saturated logo
                   shapes and "PRINT 3D" in a 5x7 bitmap font on its side
  sphere_gradient  12 mm UV sphere (48 x 24), hue around, lightness pole to pole

Usage: make_textured_models.py OUT_DIR.  Standard library only, so it runs
anywhere: PNGs are written with zlib+struct, noise from a fixed seed (the
same bytes every run). Units are glTF's metres. Every mesh is checked to be
closed and outward-facing after welding equal positions, as prepare needs.
"""
import colorsys, json, math, os, random, struct, sys, zlib

MM = 0.001  # glTF positions are in metres


def write_png(path, w, h, px):
    """px: bytearray of w*h RGB bytes, rows top to bottom (glTF's v=0 row)."""
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    raw = b"".join(b"\0" + bytes(px[y * w * 3:(y + 1) * w * 3]) for y in range(h))
    with open(path, "wb") as f:  # sRGB chunk: the bytes are sRGB-encoded, as glTF expects
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"sRGB", b"\0") + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def check_closed(pos, tris):
    """Weld equal positions; every directed edge must appear once and its reverse once
    (closed, consistently oriented), and the signed volume must be positive (outward)."""
    key = [struct.pack("<3f", *p) for p in pos]  # compare as the float32s written
    ids, weld = {}, [0] * len(pos)
    for i, k in enumerate(key):
        weld[i] = ids.setdefault(k, len(ids))
    edges, vol = set(), 0.0
    for a, b, c in tris:
        for e in ((weld[a], weld[b]), (weld[b], weld[c]), (weld[c], weld[a])):
            assert e[0] != e[1] and e not in edges, "degenerate or repeated edge"
            edges.add(e)
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = pos[a], pos[b], pos[c]
        vol += (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6
    assert all((b, a) in edges for a, b in edges), "open or inconsistently oriented"
    assert vol > 0, "inward-facing"


def write_gltf(out, name, pos, uv, tris, tex_w, tex_h, tex):
    check_closed(pos, tris)
    write_png(os.path.join(out, name + ".png"), tex_w, tex_h, tex)
    pos = [tuple(c + 0.0 for c in p) for p in pos]  # no -0.0: the same bits as +0.0 when welded
    blob = b"".join(struct.pack("<3f", *p) for p in pos) + b"".join(struct.pack("<2f", *t) for t in uv) \
        + b"".join(struct.pack("<3I", *t) for t in tris)
    with open(os.path.join(out, name + ".bin"), "wb") as f:
        f.write(blob)
    n, np_, nu = len(pos), 12 * len(pos), 8 * len(pos)
    view = lambda off, ln, tgt: {"buffer": 0, "byteOffset": off, "byteLength": ln, "target": tgt}
    doc = {
        "asset": {"version": "2.0", "generator": "printlight scripts/make_textured_models.py"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": name}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                    "indices": 2, "material": 0, "mode": 4}]}],
        "materials": [{"name": name, "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                              "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "textures": [{"source": 0, "sampler": 0}], "images": [{"uri": name + ".png"}],
        "samplers": [{"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497}],
        "buffers": [{"uri": name + ".bin", "byteLength": len(blob)}],
        "bufferViews": [view(0, np_, 34962), view(np_, nu, 34962), view(np_ + nu, 12 * len(tris), 34963)],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": n, "type": "VEC3",
             "min": [min(p[i] for p in pos) for i in range(3)], "max": [max(p[i] for p in pos) for i in range(3)]},
            {"bufferView": 1, "componentType": 5126, "count": n, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5125, "count": 3 * len(tris), "type": "SCALAR"}],
    }
    with open(os.path.join(out, name + ".gltf"), "w") as f:
        json.dump(doc, f, indent=1)
    print(f"{name}: {n} vertices, {len(tris)} triangles, texture {tex_w}x{tex_h}")


# ---- a) box_photo: value noise, a few octaves with 1/f amplitudes like a photograph's spectrum
def box_photo(out):
    W = H = 512
    rng = random.Random(20240607)
    lattice = [rng.random() for _ in range(256 * 256)]

    def noise(x, y):  # value noise, smoothstep-interpolated lattice values in [0, 1]
        xi, yi = math.floor(x), math.floor(y)
        fx, fy = x - xi, y - yi
        fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
        v = lambda i, j: lattice[((yi + j) & 255) << 8 | ((xi + i) & 255)]
        top = v(0, 0) + (v(1, 0) - v(0, 0)) * fx
        return top + (v(0, 1) + (v(1, 1) - v(0, 1)) * fx - top) * fy

    def fbm(x, y, off, octaves=4):  # cells of 4, 2, 1, 0.5 mm; result roughly in [0, 1]
        s, a, f = 0.0, 0.5, 0.25
        for k in range(octaves):
            s += a * noise(x * f + off + 17 * k, y * f - off + 31 * k)
            a, f = a * 0.5, f * 2
        return s / (1 - 0.5 ** octaves)

    # foliage dark/light, olive-earth, skin, light skin, muted sky: hues a photo of people outdoors has
    stops = [(55, 90, 45), (105, 140, 60), (150, 130, 90), (200, 150, 120), (232, 188, 160), (125, 145, 170)]
    px = bytearray(W * H * 3)
    for y in range(H):
        for x in range(W):
            mx, my = x * 12 / (W / 3), y * 12 / (H / 2)  # millimetres on the face (tiles are 1/3 x 1/2)
            t = min(max((fbm(mx, my, 0.0) - 0.25) * 2, 0), 0.999) * (len(stops) - 1)
            i, f = int(t), t - int(t)
            shade = 0.7 + 0.6 * fbm(mx, my, 91.0, 3)  # light and shadow, independent of hue
            tint = (fbm(mx, my, 57.0, 2) - 0.5) * 40  # a little warm/cool variation
            for c in range(3):
                v = (stops[i][c] + (stops[i + 1][c] - stops[i][c]) * f) * shade + (tint if c == 0 else -tint if c == 2 else 0)
                px[(y * W + x) * 3 + c] = min(max(int(v + 0.5), 0), 255)
    # six faces: (outward normal, du, dv) with du x dv = normal, so (s,t) order below is CCW outside
    faces = [((1, 0, 0), (0, 0, -1), (0, 1, 0)), ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
             ((0, 0, 1), (1, 0, 0), (0, 1, 0)), ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
             ((0, 1, 0), (1, 0, 0), (0, 0, -1)), ((0, -1, 0), (1, 0, 0), (0, 0, 1))]
    h, pos, uv, tris = 6 * MM, [], [], []
    for k, (n, du, dv) in enumerate(faces):
        u0, v0 = (k % 3) / 3, (k // 3) / 2
        base = len(pos)
        for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            pos.append(tuple(h * (n[i] + s * du[i] + t * dv[i]) for i in range(3)))
            # inset by one texel so bilinear filtering never reads the neighbouring tile
            uv.append((u0 + (1 + (s + 1) / 2 * (W / 3 - 2)) / W, v0 + (1 + (1 - t) / 2 * (H / 2 - 2)) / H))
        tris += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    write_gltf(out, "box_photo", pos, uv, tris, W, H, px)


# ---- b) cylinder_logo: flat colours, hard edges, thin text: what a compensation must keep sharp
FONT = {  # 5x7 bitmap, rows top to bottom
    "P": ["11110", "10001", "10001", "11110", "10000", "10000", "10000"],
    "R": ["11110", "10001", "10001", "11110", "10100", "10010", "10001"],
    "I": ["01110", "00100", "00100", "00100", "00100", "00100", "01110"],
    "N": ["10001", "11001", "10101", "10011", "10001", "10001", "10001"],
    "T": ["11111", "00100", "00100", "00100", "00100", "00100", "00100"],
    "3": ["11110", "00001", "00001", "01110", "00001", "00001", "11110"],
    "D": ["11100", "10010", "10001", "10001", "10001", "10010", "11100"],
    " ": ["00000"] * 7,
}
RED, GREEN, BLUE, CYAN, MAGENTA, YELLOW, BLACK = (230, 30, 35), (20, 160, 60), (30, 60, 200), \
    (0, 170, 230), (220, 0, 140), (255, 220, 0), (20, 20, 20)


def cylinder_logo(out):
    W = H = 512
    R, SEG = 6.0, 64
    C = 2 * math.pi * R  # the side spans u in [0,1] = C mm and image rows 0..255 = 12 mm
    px = bytearray([255] * (W * H * 3))  # white background (the white resin)

    def paint(x0, y0, x1, y1, inside, col, sx, sy, ox=0, oy=0):
        """Fill pixels of the box [x0,x1)x[y0,y1) mm whose centre satisfies inside(x, y);
        sx, sy: pixels per mm; ox, oy: the region's pixel origin."""
        for py in range(max(int(y0 * sy), 0), min(int(y1 * sy) + 1, 256)):
            for qx in range(int(x0 * sx), int(x1 * sx) + 1):
                x, y = (qx + 0.5) / sx, (py + 0.5) / sy
                if inside(x, y):
                    o = ((oy + py) * W + ox + qx % W) * 3  # wrap around the side's seam
                    px[o:o + 3] = bytes(col)

    sx, sy = W / C, 256 / 12.0
    colours = [RED, GREEN, BLUE, CYAN, MAGENTA, YELLOW, BLACK]
    for k, col in enumerate(colours):  # a band of stripes at the top, one per colour
        paint(k * C / 7, 0.6, k * C / 7 + C / 7 * 0.75, 2.4, lambda x, y: True, col, sx, sy)
    for k, col in enumerate(colours):  # discs and triangles alternate along the bottom
        cx = (k + 0.5) * C / 7
        if k % 2 == 0:
            paint(cx - 1.6, 8.2, cx + 1.6, 11.4, lambda x, y, cx=cx: (x - cx) ** 2 + (y - 9.8) ** 2 < 1.6 ** 2, col, sx, sy)
        else:  # apex up, base at y = 11.4 mm
            paint(cx - 1.8, 8.2, cx + 1.8, 11.4, lambda x, y, cx=cx: y < 11.4 and abs(x - cx) < (y - 8.2) / 3.2 * 1.8, col, sx, sy)
    text, fp = "PRINT 3D", 0.36  # font pixel 0.36 mm: text 2.5 mm tall, strokes well above a voxel
    x0 = (C - (len(text) * 6 - 1) * fp) / 2
    for i, ch in enumerate(text):
        for r, row in enumerate(FONT[ch]):
            for c, bit in enumerate(row):
                if bit == "1":
                    gx, gy = x0 + (i * 6 + c) * fp, 4.0 + r * fp
                    paint(gx, gy, gx + fp, gy + fp, lambda x, y, gx=gx, gy=gy: gx <= x < gx + fp and gy <= y < gy + fp, BLACK, sx, sy)
    # the caps: lower half of the image, top cap left, bottom cap right; concentric rings
    for ox in (0, 256):
        ring = [(5.6, CYAN), (4.2, MAGENTA), (2.8, YELLOW), (1.4, BLACK)]
        for rad, col in ring:
            paint(6 - rad, 6 - rad, 6 + rad, 6 + rad, lambda x, y, rad=rad: (x - 6) ** 2 + (y - 6) ** 2 < rad ** 2, col, 256 / 12, 256 / 12, ox, 256)

    # mesh, axis along +y (glTF's up); seam vertices repeated with u = 1, positions from j % SEG
    ring_pt = lambda j, y: (R * MM * math.cos(2 * math.pi * (j % SEG) / SEG), y, -R * MM * math.sin(2 * math.pi * (j % SEG) / SEG))
    pos, uv, tris, hh = [], [], [], 6 * MM
    inset_v = (1 / H, 255 / H)  # side rows 0..255 of the image, half a texel in from both edges
    for j in range(SEG + 1):
        pos += [ring_pt(j, hh), ring_pt(j, -hh)]
        uv += [(j / SEG, inset_v[0]), (j / SEG, inset_v[1])]
    for j in range(SEG):  # down then around is outward (d/dtheta x d/dphi)
        a, b, c, d = 2 * j, 2 * j + 1, 2 * j + 3, 2 * j + 2
        tris += [(a, b, c), (a, c, d)]
    for y, ox, flip in ((hh, 0, False), (-hh, 256, True)):  # caps: planar map into a 256x256 square
        centre = len(pos)
        pos.append((0.0, y, 0.0)); uv.append(((ox + 128) / W, 384 / H))
        for j in range(SEG):
            p = ring_pt(j, y)
            pos.append(p); uv.append(((ox + 128 + p[0] / MM * 127 / R) / W, (384 + p[2] / MM * 127 / R) / H))
        for j in range(SEG):
            p, q = centre + 1 + j, centre + 1 + (j + 1) % SEG
            tris.append((centre, q, p) if flip else (centre, p, q))
    write_gltf(out, "cylinder_logo", pos, uv, tris, W, H, px)


# ---- c) sphere_gradient: smooth, low-frequency colour; the easy case for any loop
def sphere_gradient(out):
    W = H = 256
    px = bytearray(W * H * 3)
    for y in range(H):
        light = 0.2 + 0.62 * (y + 0.5) / H  # dark (L 0.2) at the top pole to light (0.82): no pure black/white
        for x in range(W):
            r, g, b = colorsys.hls_to_rgb((x + 0.5) / W, light, 0.55)  # moderate saturation: within CMY's reach
            px[(y * W + x) * 3:(y * W + x) * 3 + 3] = bytes(int(c * 255 + 0.5) for c in (r, g, b))
    NU, NV, R = 48, 24, 6 * MM
    pos, uv, tris = [], [], []
    for i in range(NV + 1):
        th = math.pi * i / NV
        for j in range(NU + 1):
            ph = 2 * math.pi * (j % NU) / NU
            p = (0.0, R, 0.0) if i == 0 else (0.0, -R, 0.0) if i == NV else \
                (R * math.sin(th) * math.cos(ph), R * math.cos(th), -R * math.sin(th) * math.sin(ph))
            pos.append(p); uv.append((j / NU, i / NV))
    for i in range(NV):
        for j in range(NU):
            a, b, c, d = i * (NU + 1) + j, (i + 1) * (NU + 1) + j, (i + 1) * (NU + 1) + j + 1, i * (NU + 1) + j + 1
            if i != NV - 1: tris.append((a, b, c))  # skip the triangles that collapse at the poles
            if i != 0: tris.append((a, c, d))
    write_gltf(out, "sphere_gradient", pos, uv, tris, W, H, px)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: make_textured_models.py OUT_DIR")
    os.makedirs(sys.argv[1], exist_ok=True)
    for make in (box_photo, cylinder_logo, sphere_gradient):
        make(sys.argv[1])
