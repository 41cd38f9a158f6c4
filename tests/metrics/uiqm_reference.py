# Pure-Python ports (no numpy) of FUnIE-GAN Evaluation/uqim_utils.py (Python-3 port: real-valued
# k in UIConM's weight) and xueleichen nevaluate.py (scikit-image 0.17 sobel, rgb2gray), line by
# line, to give the C++ tests independent values. Image: LCG levels.
import math
W, H = 37, 29
state = 12345
img = [[[0]*3 for _ in range(W)] for _ in range(H)]
for y in range(H):
    for x in range(W):
        for c in range(3):
            state = (state * 1103515245 + 12345) % (1 << 31)
            img[y][x][c] = (state >> 16) % 256

def chan(c): return [[img[y][x][c] for x in range(W)] for y in range(H)]

# ---- variant A
def mu_a(x):
    x = sorted(x); K = len(x)
    TL = math.ceil(0.1*K); TR = math.floor(0.1*K)
    return (1/(K-TL-TR)) * sum(x[int(TL+1):int(K-TR)])
def s_a(x, mu): return sum((p-mu)**2 for p in x)/len(x)
def uicm_a():
    R = [img[y][x][0] for y in range(H) for x in range(W)]
    G = [img[y][x][1] for y in range(H) for x in range(W)]
    B = [img[y][x][2] for y in range(H) for x in range(W)]
    RG = [r-g for r,g in zip(R,G)]; YB = [(r+g)/2-b for r,g,b in zip(R,G,B)]
    m1, m2 = mu_a(RG), mu_a(YB)
    return -0.0268*math.sqrt(m1*m1+m2*m2) + 0.1586*math.sqrt(s_a(RG,m1)+s_a(YB,m2))
def refl(i, n): return 0 if i < 0 else (n-1 if i >= n else i)
def ndsobel(a, axis):
    out = [[0.0]*W for _ in range(H)]
    for y in range(H):
        for x in range(W):
            g = lambda dy, dx: a[refl(y+dy,H)][refl(x+dx,W)]
            if axis == 0:  # derivative along rows, smoothing along columns
                out[y][x] = sum(w*(g(1,dx)-g(-1,dx)) for dx,w in ((-1,1),(0,2),(1,1)))
            else:
                out[y][x] = sum(w*(g(dy,1)-g(dy,-1)) for dy,w in ((-1,1),(0,2),(1,1)))
    return out
def sobel_a(a):
    dx, dy = ndsobel(a,0), ndsobel(a,1)
    mag = [[math.hypot(dx[y][x], dy[y][x]) for x in range(W)] for y in range(H)]
    m = max(max(r) for r in mag)
    return [[v*255.0/m for v in r] for r in mag]
def eme(x, ws):
    k1 = int(W/ws); k2 = int(H/ws); w = 2./(k1*k2); val = 0
    for l in range(k1):
        for k in range(k2):
            blk = [x[yy][xx] for yy in range(k*ws,(k+1)*ws) for xx in range(l*ws,(l+1)*ws)]
            mx, mn = max(blk), min(blk)
            if mn == 0.0 or mx == 0.0: val += 0
            else: val += math.log(mx/mn)
    return w*val
def uism_a():
    lam = (0.299, 0.587, 0.144); s = 0
    for c in range(3):
        ch = chan(c); sb = sobel_a(ch)
        s += lam[c]*eme([[sb[y][x]*ch[y][x] for x in range(W)] for y in range(H)], 10)
    return s
def uiconm_a():
    k1r = W/10; k2r = H/10; k1 = int(k1r); k2 = int(k2r); val = 0
    for l in range(k1):
        for k in range(k2):
            blk = [img[yy][xx][c] for yy in range(k*10,(k+1)*10) for xx in range(l*10,(l+1)*10) for c in range(3)]
            mx, mn = max(blk), min(blk); top = mx-mn; bot = mx+mn
            if bot == 0 or top == 0: continue
            val += (top/bot)*math.log(top/bot)
    return -1./(k1r*k2r)*val
# ---- variant B
def uicm_b():
    rg = sorted(((img[y][x][0]-img[y][x][1]) % 256) for y in range(H) for x in range(W))
    yb = sorted(((img[y][x][0]+img[y][x][1]) % 256)/2 - img[y][x][2] for y in range(H) for x in range(W))
    T = int(0.1*len(rg))
    def mv(v):
        t = v[T:len(v)-T]; m = sum(t)/len(t); return m, sum((q-m)**2 for q in t)/len(t)
    (u1, s1), (u2, s2) = mv(rg), mv(yb)
    return -0.0268*math.sqrt(u1**2+u2**2) + 0.1586*math.sqrt(s1+s2)
def sobel_b(a):
    f = [[v/255.0 for v in r] for r in a]
    out = [[0.0]*W for _ in range(H)]
    for y in range(1,H-1):
        for x in range(1,W-1):
            h = (f[y-1][x-1]+2*f[y-1][x]+f[y-1][x+1] - f[y+1][x-1]-2*f[y+1][x]-f[y+1][x+1])/4.0
            v = (f[y-1][x-1]+2*f[y][x-1]+f[y+1][x-1] - f[y-1][x+1]-2*f[y][x+1]-f[y+1][x+1])/4.0
            out[y][x] = math.sqrt(h*h+v*v)/math.sqrt(2)
    return out
def blocks8():
    nx = math.ceil(H/8); ny = math.ceil(W/8)
    for i in range(nx):
        for j in range(ny):
            yield (i*8, (i+1)*8 if i < nx-1 else H, j*8, (j+1)*8 if j < ny-1 else W)
def eme_b(ch):
    nx = math.ceil(H/8); ny = math.ceil(W/8); w = 2./(nx*ny); e = 0
    for y0,y1,x0,x1 in blocks8():
        blk = [ch[y][x] for y in range(y0,y1) for x in range(x0,x1)]
        mn, mx = float(min(blk)), float(max(blk))
        if mn == 0: mn += 1
        if mx == 0: mx += 1
        e += w*math.log(mx/mn)
    return e
def uism_b():
    lam = (0.299, 0.587, 0.114); s = 0
    for c in range(3):
        ch = chan(c); sb = sobel_b(ch)
        s += lam[c]*eme_b([[round(ch[y][x]*sb[y][x]) for x in range(W)] for y in range(H)])
    return s
def uiconm_b():
    g = [[img[y][x][0]/255*0.2125 + img[y][x][1]/255*0.7154 + img[y][x][2]/255*0.0721 for x in range(W)] for y in range(H)]
    nx = math.ceil(H/8); ny = math.ceil(W/8); w = 1./(nx*ny); s = 0
    for y0,y1,x0,x1 in blocks8():
        blk = [g[y][x] for y in range(y0,y1) for x in range(x0,x1)]
        mn, mx = min(blk), max(blk)
        top = 1026*(mx-mn)/(1026-mn); bot = mx+mn-mx*mn/1026; m = top/bot
        if m != 0: s += m*math.log(m)
    return 1026 - 1026*(1-s/1026)**w
a = (uicm_a(), uism_a(), uiconm_a()); b = (uicm_b(), uism_b(), uiconm_b())
for n, p in (("A", a), ("B", b)):
    print(n, "uicm %.12g uism %.12g uiconm %.12g uiqm %.12g" % (p[0], p[1], p[2], 0.0282*p[0]+0.2953*p[1]+3.5753*p[2]))
