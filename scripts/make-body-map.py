#!/usr/bin/env python3
"""Make a synthetic whole-torso label map, laid out like TotalSegmentator's.

A second map for the --labels benchmark (scripts/bench-labels --map body),
beside make-label-map.py's CT split into blocks: there every tissue class
is cut into 5x5x5 regions, so most of the surface lies between two labels
and is written twice. In an organ atlas most of the body is unlabelled
(label 0: fat, soft tissue, air) and the structures are separate or touch
over part of their surface: vertebrae with unlabelled discs between them,
ribs meeting the spine, lung lobes and heart chambers sharing walls,
vessels running along and into organs, muscles on the bones.

Each structure is painted into SIZE^3 samples (a torso of about 40 x 30 x
50 cm at SIZE 512) as a union of ellipsoids or of capsules along a path, in
a fixed order (a later one wins where two overlap, so they share a
boundary there); positions are jittered by a seeded random generator, so
the map is the same on every run. 16 muscles, 24 vertebrae, the spinal
cord, 24 ribs, the sternum, 5 lung lobes, trachea and a bronchus, the left
bronchus, 4 heart chambers, 9 vessels, 19 abdominal, pelvic and neck
organs, 9 bones of the pelvis, legs and shoulders: 114 labels, numbered
from 1, each present (at SIZE 512: 90% of the samples unlabelled).

    make-body-map.py OUT.nrrd [--size 512] [--seed 1]

Writes a raw uint16 NRRD (spacing 1) and prints the number of labels.
Needs: python3 -m pip install numpy
"""

import argparse

import numpy as np


class Map:
    """The label volume (z, y, x) and the next label number."""

    def __init__(self, n, rng):
        self.n = n
        self.s = n / 512.0
        self.rng = rng
        self.v = np.zeros((n, n, n), dtype=np.uint16)
        self.next = 1

    def label(self):
        """A new label number."""
        k = self.next
        self.next += 1
        return k

    def _box(self, lo, hi):
        """Index ranges of the box [lo, hi] (x, y, z, in samples), clipped."""
        lo = [max(0, int(np.floor(a))) for a in lo]
        hi = [min(self.n, int(np.ceil(b)) + 1) for b in hi]
        if any(a >= b for a, b in zip(lo, hi)):
            return None
        return [np.arange(a, b, dtype=np.float32) for a, b in zip(lo, hi)], lo, hi

    def ellipsoid(self, k, c, r, keep=None):
        """Paints label `k` on the ellipsoid of centre `c` and semi-axes `r`
        (x, y, z; in units of the 512 grid); `keep(x, y, z)` masks it."""
        c = [a * self.s for a in c]
        r = [max(a * self.s, 1.0) for a in r]
        box = self._box([a - b for a, b in zip(c, r)], [a + b for a, b in zip(c, r)])
        if box is None:
            return
        (x, y, z), lo, hi = box
        d = (
            ((z - c[2]) / r[2])[:, None, None] ** 2
            + ((y - c[1]) / r[1])[None, :, None] ** 2
            + ((x - c[0]) / r[0])[None, None, :] ** 2
        )
        inside = d <= 1.0
        if keep is not None:
            inside &= keep(x[None, None, :], y[None, :, None], z[:, None, None])
        region = self.v[lo[2] : hi[2], lo[1] : hi[1], lo[0] : hi[0]]
        region[inside] = k

    def blob(self, k, c, r, parts=4, spread=0.35):
        """Label `k` on an irregular blob: the ellipsoid (`c`, `r`) and
        `parts` smaller ones jittered about it."""
        self.ellipsoid(k, c, r)
        for _ in range(parts):
            off = [a * spread * self.rng.uniform(-1, 1) for a in r]
            rr = [a * self.rng.uniform(0.5, 0.8) for a in r]
            self.ellipsoid(k, [a + b for a, b in zip(c, off)], rr)

    def tube(self, k, points, radius):
        """Label `k` on capsules of `radius` along the path `points`."""
        pts = [np.array(p, dtype=np.float32) * self.s for p in points]
        rad = radius * self.s
        for a, b in zip(pts, pts[1:]):
            box = self._box(np.minimum(a, b) - rad, np.maximum(a, b) + rad)
            if box is None:
                continue
            (x, y, z), lo, hi = box
            ab = b - a
            length2 = max(float(ab @ ab), 1e-9)
            px = x[None, None, :] - a[0]
            py = y[None, :, None] - a[1]
            pz = z[:, None, None] - a[2]
            t = np.clip((px * ab[0] + py * ab[1] + pz * ab[2]) / length2, 0.0, 1.0)
            d2 = (px - t * ab[0]) ** 2 + (py - t * ab[1]) ** 2 + (pz - t * ab[2]) ** 2
            region = self.v[lo[2] : hi[2], lo[1] : hi[1], lo[0] : hi[0]]
            region[d2 <= rad * rad] = k


def arc(c, rx, ry, a0, a1, z0, z1, steps=12):
    """Points on an elliptic arc about `c` (x, y) from angle a0 to a1
    (radians), rising linearly from z0 to z1."""
    return [
        (c[0] + rx * np.cos(a), c[1] + ry * np.sin(a), z0 + (z1 - z0) * i / steps)
        for i, a in enumerate(np.linspace(a0, a1, steps + 1))
    ]


def paint(m):
    """Every structure, in painting order (z up: 0 is the pelvis, 511 the
    neck; y grows towards the back)."""
    rng = m.rng
    cx, spine_y = 256, 330
    # Muscles first: the bones and organs painted later cut into them.
    for side in (-1, 1):
        m.blob(m.label(), (cx + side * 45, spine_y + 55, 250), (28, 25, 200), parts=6, spread=0.2)  # autochthon
        m.blob(m.label(), (cx + side * 70, 300, 120), (20, 22, 70), parts=3)  # iliopsoas
        m.blob(m.label(), (cx + side * 110, 360, 50), (55, 45, 55), parts=4)  # gluteus maximus
        m.blob(m.label(), (cx + side * 130, 330, 70), (35, 30, 40), parts=3)  # gluteus medius
        m.blob(m.label(), (cx + side * 135, 320, 60), (22, 20, 25), parts=2)  # gluteus minimus
        m.blob(m.label(), (cx + side * 150, 250, 20), (30, 30, 40), parts=3)  # quadriceps
        m.blob(m.label(), (cx + side * 120, 300, 470), (40, 30, 25), parts=3)  # trapezius part
        m.blob(m.label(), (cx + side * 160, 300, 430), (30, 40, 30), parts=3)  # deltoid
    # Spine: 24 vertebrae with unlabelled discs, the cord through them.
    height = 460 / 24
    for i in range(24):
        z = 30 + i * height
        k = m.label()
        r = 20 + 6 * (i < 12)  # lumbar bodies wider
        m.ellipsoid(k, (cx, spine_y, z + height * 0.4), (r, r * 0.8, height * 0.38))
        ring = lambda x, y, z: (x - cx * m.s) ** 2 + (y - (spine_y + 38) * m.s) ** 2 >= (10 * m.s) ** 2
        m.ellipsoid(k, (cx, spine_y + 38, z + height * 0.4), (17, 14, height * 0.3), keep=ring)
        m.tube(k, [(cx, spine_y + 50, z + height * 0.4), (cx, spine_y + 72, z + height * 0.2)], 5)
    m.tube(m.label(), [(cx, spine_y + 38, 30), (cx, spine_y + 36, 300), (cx, spine_y + 40, 505)], 7)  # cord
    # Ribs: 12 pairs from the thoracic vertebrae round the chest, falling.
    for i in range(12):
        z = 30 + (12 + i) * height + height * 0.4
        for side in (-1, 1):
            a0 = np.pi / 2 - side * 0.25
            a1 = np.pi / 2 - side * (np.pi - 0.5 - 0.03 * i)
            path = arc((cx, 250), 150 - 3 * abs(i - 6), 105, a0, a1, z, z - 45, steps=16)
            m.tube(m.label(), [(cx + side * 22, spine_y, z)] + path, 5)
    m.blob(m.label(), (cx, 148, 400), (12, 8, 60), parts=2, spread=0.2)  # sternum
    # Lungs: each split into lobes by planes (the lobes share a fissure).
    for side, lobes in ((-1, 3), (1, 2)):
        lc = (cx + side * 80, 260, 400)
        cuts = np.linspace(330, 470, lobes + 1)[1:-1]
        for j in range(lobes):
            lo_z = -1e9 if j == 0 else cuts[j - 1]
            hi_z = 1e9 if j == lobes - 1 else cuts[j]
            keep = lambda x, y, z, lo=lo_z, hi=hi_z: (z - 0.3 * (y - 260 * m.s) >= lo * m.s) & (
                z - 0.3 * (y - 260 * m.s) < hi * m.s
            )
            m.ellipsoid(m.label(), lc, (62, 80, 95), keep=keep)
    m.tube(m.label(), [(cx, 200, 505), (cx, 205, 440), (cx - 40, 220, 410)], 9)  # trachea, right bronchus
    m.tube(m.label(), [(cx, 205, 440), (cx + 40, 220, 405)], 7)  # left bronchus
    # Heart: four chambers, quarters of one ellipsoid.
    hc = (cx + 20, 200, 350)
    for qx in (0, 1):
        for qz in (0, 1):
            keep = lambda x, y, z, qx=qx, qz=qz: ((x >= hc[0] * m.s) == bool(qx)) & (
                (z >= hc[2] * m.s) == bool(qz)
            )
            m.ellipsoid(m.label(), hc, (55, 45, 50), keep=keep)
    # Vessels.
    aorta = [(cx + 20, 200, 400), (cx + 10, 230, 450), (cx - 20, 290, 440), (cx - 25, 285, 300), (cx - 20, 280, 150)]
    m.tube(m.label(), aorta, 12)
    m.tube(m.label(), [(cx + 30, 180, 390), (cx + 40, 200, 430), (cx + 70, 230, 420)], 10)  # pulmonary artery
    m.tube(m.label(), [(cx + 30, 270, 120), (cx + 32, 265, 300), (cx + 25, 215, 340)], 11)  # inferior vena cava
    m.tube(m.label(), [(cx + 60, 240, 270), (cx + 20, 250, 250)], 7)  # portal vein
    m.tube(m.label(), [(cx - 30, 185, 470), (cx - 10, 200, 400)], 9)  # superior vena cava
    for side in (-1, 1):
        m.tube(m.label(), [(cx - 20, 280, 150), (cx + side * 60, 270, 90), (cx + side * 110, 240, 20)], 7)  # iliac artery
        m.tube(m.label(), [(cx + 30, 270, 120), (cx + side * 70, 285, 85), (cx + side * 118, 255, 15)], 8)  # iliac vein
    # Abdominal and pelvic organs.
    m.blob(m.label(), (cx - 70, 230, 280), (85, 70, 50), parts=6)  # liver
    m.blob(m.label(), (cx + 110, 290, 290), (35, 30, 40), parts=3)  # spleen
    m.blob(m.label(), (cx + 60, 200, 280), (45, 35, 35), parts=4)  # stomach
    m.blob(m.label(), (cx + 20, 250, 240), (50, 12, 12), parts=3, spread=0.5)  # pancreas
    for side in (-1, 1):
        m.blob(m.label(), (cx + side * 75, 305, 225), (22, 18, 40), parts=2, spread=0.2)  # kidney
        m.blob(m.label(), (cx + side * 65, 300, 272), (8, 6, 10), parts=1)  # adrenal gland
        m.tube(m.label(), [(cx + side * 70, 300, 195), (cx + side * 60, 280, 120), (cx + side * 30, 200, 70)], 3)  # ureter
    m.blob(m.label(), (cx - 60, 190, 250), (14, 12, 18), parts=1)  # gallbladder
    m.tube(m.label(), arc((cx, 230), 110, 90, -0.3, 3.5, 220, 140, steps=14), 16)  # colon
    m.tube(m.label(), [(cx - 20, 240, 270), (cx - 40, 230, 240), (cx + 10, 230, 225), (cx + 40, 240, 240)], 10)  # duodenum
    m.blob(m.label(), (cx, 190, 170), (60, 45, 40), parts=8, spread=0.6)  # small bowel
    m.blob(m.label(), (cx, 180, 60), (35, 30, 30), parts=2)  # urinary bladder
    m.blob(m.label(), (cx, 200, 25), (14, 12, 12), parts=1)  # prostate
    m.tube(m.label(), [(cx - 5, 260, 500), (cx + 5, 270, 400), (cx + 25, 220, 300)], 7)  # esophagus
    m.blob(m.label(), (cx, 260, 260), (25, 20, 15), parts=3)  # lymph node cluster
    m.blob(m.label(), (cx - 15, 140, 490), (20, 12, 15), parts=2)  # thyroid gland
    # Bones of the pelvis, legs and shoulders.
    for side in (-1, 1):
        m.blob(m.label(), (cx + side * 100, 300, 100), (55, 30, 60), parts=5, spread=0.4)  # hip
        m.tube(m.label(), [(cx + side * 130, 260, 60), (cx + side * 140, 250, 40), (cx + side * 150, 240, 0)], 14)  # femur
        m.blob(m.label(), (cx + side * 140, 340, 440), (40, 12, 45), parts=3)  # scapula
        m.tube(m.label(), [(cx + side * 20, 150, 470), (cx + side * 90, 180, 485), (cx + side * 150, 240, 480)], 6)  # clavicle
    m.blob(m.label(), (cx, spine_y + 20, 20), (40, 25, 25), parts=3)  # sacrum
    return m.next - 1


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--size", type=int, default=512)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    m = Map(args.size, np.random.default_rng(args.seed))
    count = paint(m)
    n = args.size
    with open(args.out, "wb") as f:
        f.write(
            (
                "NRRD0004\ntype: uint16\ndimension: 3\n"
                f"sizes: {n} {n} {n}\nspacing: 1 1 1\nendian: little\nencoding: raw\n\n"
            ).encode()
        )
        f.write(m.v.astype("<u2", copy=False).tobytes())
    print(count)


if __name__ == "__main__":
    main()
