#!/usr/bin/env python3
"""How close a thinned predictions.png is to the plot of every row (docs/PERFORMANCE.md, THR6).

  plot_ink.py fullbin PREDICTIONS.csv TRACK.csv OUT.bin
      predictions.csv of one point (`predvs predict`) and the track's truth columns (4 and 5) ->
      the 28-column float64 table of predictions_plot.bin, every row (for predictions.gp with
      data = 'OUT.bin': the plot of every row, the reference).
  plot_ink.py diff REFERENCE.png OTHER.png
      classes every pixel of the two plot areas of the 1200x850 predictions.png (white, dark,
      coloured) and prints how many differ, and the inked and dark pixels of each.
  plot_ink.py crop IN.png OUT.png X0 Y0 X1 Y1 K
      a crop of IN.png, each pixel made K x K (to look at).
No third-party module: PNGs as pngcairo writes them (8-bit RGB/RGBA, not interlaced).
"""
import array, struct, sys, zlib


def read_png(path):
    d = open(path, 'rb').read()
    assert d[:8] == b'\x89PNG\r\n\x1a\n', path
    i, idat = 8, b''
    while i < len(d):
        n, t = struct.unpack('>I4s', d[i:i + 8])
        body = d[i + 8:i + 8 + n]
        i += 12 + n
        if t == b'IHDR':
            w, h, bd, ct, _, _, il = struct.unpack('>IIBBBBB', body)
        elif t == b'IDAT':
            idat += body
    assert bd == 8 and il == 0 and ct in (2, 6), (path, bd, ct, il)
    bpp = 3 if ct == 2 else 4
    raw, stride = zlib.decompress(idat), w * bpp
    rows, prev, p = [], bytearray(stride), 0
    for _ in range(h):
        f, line = raw[p], bytearray(raw[p + 1:p + 1 + stride])
        p += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append([tuple(line[x * bpp:x * bpp + 3]) for x in range(w)])
        prev = line
    return rows


def write_png(path, rows):
    h, w = len(rows), len(rows[0])
    raw = b''.join(b'\x00' + bytes(v for px in r for v in px) for r in rows)

    def chunk(t, b):
        return struct.pack('>I', len(b)) + t + b + struct.pack('>I', zlib.crc32(t + b))
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0)) +
                           chunk(b'IDAT', zlib.compress(raw)) + chunk(b'IEND', b''))


def pixel_class(px):
    r, g, b = px
    s = r + g + b
    if s > 700:
        return 0  # background
    if max(px) - min(px) < 40 and s < 300:
        return 1  # black
    return 2      # coloured or grey


def diff(ref_path, other_path):
    a, b = read_png(ref_path), read_png(other_path)
    tot = differ = ink_a = ink_b = dark_a = dark_b = 0
    for y0, y1 in ((60, 380), (480, 795)):  # the two panels' plot areas of predictions.png
        for y in range(y0, y1):
            for x in range(88, 1015):
                ca, cb = pixel_class(a[y][x]), pixel_class(b[y][x])
                tot += 1
                differ += ca != cb
                ink_a += ca != 0
                ink_b += cb != 0
                dark_a += ca == 1
                dark_b += cb == 1
    print(f"{other_path}: {tot} pixels, class differs on {differ} ({100 * differ / tot:.2f} %); "
          f"inked {ink_a} (reference) vs {ink_b}; dark {dark_a} vs {dark_b}")


def fullbin(pred, track, out):
    nan = float('nan')

    def num(s):
        return float(s) if s.strip() else nan
    with open(pred) as fp, open(track) as ft, open(out, 'wb') as fo:
        fp.readline()
        ft.readline()
        buf = array.array('d')
        for lp, lt in zip(fp, ft):
            p, t = lp.rstrip('\n').split(','), lt.rstrip('\n').split(',')
            buf.extend([num(p[0]), num(p[1]), num(p[2]), num(p[3]), num(t[3]), num(t[4])] + [num(x) for x in p[4:]])
            if len(buf) > 1 << 20:
                buf.tofile(fo)
                buf = array.array('d')
        buf.tofile(fo)


if __name__ == '__main__':
    cmd, args = sys.argv[1] if len(sys.argv) > 1 else '', sys.argv[2:]
    if cmd == 'diff' and len(args) == 2:
        diff(*args)
    elif cmd == 'fullbin' and len(args) == 3:
        fullbin(*args)
    elif cmd == 'crop' and len(args) == 7:
        x0, y0, x1, y1, k = map(int, args[2:])
        write_png(args[1], [[px for px in r[x0:x1] for _ in range(k)] for r in read_png(args[0])[y0:y1] for _ in range(k)])
    else:
        sys.exit(__doc__)
