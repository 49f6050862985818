#!/usr/bin/env python3
"""Montage of tmc previews: python3 scripts/preview-wall.py OUT.png A.png B.png ...

Each picture (1024x1064, as 'tmc extract --preview' writes it) is shrunk by
4 (Lanczos) and laid out four to a row. Needs Pillow."""
import sys
from PIL import Image

out, pictures = sys.argv[1], sys.argv[2:]
thumbs = []
for path in pictures:
    im = Image.open(path).convert("RGB")
    thumbs.append(im.resize((im.width // 4, im.height // 4), Image.LANCZOS))
w, h = thumbs[0].size
cols = 4
rows = (len(thumbs) + cols - 1) // cols
wall = Image.new("RGB", (cols * w, rows * h), (30, 32, 36))
for i, t in enumerate(thumbs):
    wall.paste(t, ((i % cols) * w, (i // cols) * h))
wall.save(out, optimize=True)
