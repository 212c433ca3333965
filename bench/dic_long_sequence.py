#!/usr/bin/python3
# A long 5-Mpx DIC sequence for the memory measurement of issue 16 (docs/validation.md §7):
# A.tif (2500 x 2000, crops of DIC Challenge Sample 15) and B.tif (A moved 1 px in x), then s20/, s200/
# and s1000/ of symlinks A B B A A B B A ... (increments +1, 0, -1, 0 px). Needs numpy.
# Usage: dic_long_sequence.py OUT_DIR [SAMPLE15_DIR]
import numpy as np, struct, os, sys
def read_tif(p):  # uncompressed 8-bit strips (the DIC Challenge files)
    b = open(p,'rb').read()
    off = struct.unpack('<I', b[4:8])[0]
    n = struct.unpack('<H', b[off:off+2])[0]
    tags = {}
    for i in range(n):
        t, ty, c, v = struct.unpack('<HHII', b[off+2+12*i: off+14+12*i])
        if ty == 3 and c == 1: v &= 0xffff
        tags[t] = (ty, c, v)
    w, h = tags[256][2], tags[257][2]
    ty, c, v = tags[273]
    offs = [v] if c == 1 else list(struct.unpack('<%dI' % c, b[v:v+4*c]))
    ty, c, v2 = tags[279]
    cnts = [v2] if c == 1 else list(struct.unpack('<%dI' % c, b[v2:v2+4*c]))
    data = b''.join(b[o:o+k] for o, k in zip(offs, cnts))
    return np.frombuffer(data, np.uint8)[:w*h].reshape(h, w)
def write_tif(p, a):
    h, w = a.shape
    ifd = 8 + a.size
    entries = [(256,4,1,w),(257,4,1,h),(258,3,1,8),(259,3,1,1),(262,3,1,1),(273,4,1,8),(277,3,1,1),(278,4,1,h),(279,4,1,a.size)]
    out = b'II*\x00' + struct.pack('<I', ifd) + a.tobytes() + struct.pack('<H', len(entries))
    for t, ty, c, v in entries: out += struct.pack('<HHII', t, ty, c, v)
    out += struct.pack('<I', 0)
    open(p,'wb').write(out)
here = os.path.dirname(os.path.abspath(__file__))
d = os.path.join(here, '..', '..', 'shared', 'data', 'dic-challenge-15') + '/'
if len(sys.argv) > 2: d = sys.argv[2].rstrip('/') + '/'
out = sys.argv[1] if len(sys.argv) > 1 else '.'
os.makedirs(out, exist_ok=True)
os.chdir(out)
r, k1, k2 = read_tif(d+'reference.tif'), read_tif(d+'p200_k100_n2.tif'), read_tif(d+'p200_k200_n2.tif')
top = np.hstack([r, k1[:, :500]]); bot = np.hstack([k2, r[:, 1500:]])
A = np.ascontiguousarray(np.vstack([top, bot]))  # 2000 x 2500 = 5 Mpx
B = np.ascontiguousarray(np.roll(A, 1, axis=1))  # moved 1 px right
write_tif('A.tif', A); write_tif('B.tif', B)
for n in (20, 200, 1000):
    os.makedirs('s%d' % n, exist_ok=True)
    for k in range(n):
        src = 'A.tif' if (k % 4) in (0, 3) else 'B.tif'   # A B B A A B B A ...: increments +1, 0, -1, 0 px
        dst = 's%d/f_%04d.tif' % (n, k)
        if not os.path.lexists(dst): os.symlink(os.path.join(os.getcwd(), src), dst)
print(A.shape)
