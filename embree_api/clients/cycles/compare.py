#!/usr/bin/python3
"""Decides whether a candidate Cycles render equals Embree's within sampling noise.

    /usr/bin/python3 compare.py E1.npy E2.npy E3.npy S1.npy S2.npy [STATIC.npy]

E1, E2, E3: renders through Debian's Embree with seeds 1, 2, 3; S1, S2: the
candidate library with seeds 1 and 2; STATIC (optional): Embree, seed 1,
motion blur off. Pixels are float32 linear RGB (scene.py's .npy files).

The measure. Every comparison is a difference D = X - E1 between a render X
and Embree's seed-1 render, per pixel and colour channel:
- sigma(p), the noise of such a difference at pixel p, is estimated from
  E3 - E1: the root mean square over a 5x5 window, never below SIGMA_FLOOR;
- MAD = mean |D|;
- tail = the fraction of pixel-channels with |D| > K_SIGMA * sigma(p);
- biased blocks = the number of BxB blocks (per channel, B = 8, 16, 32)
  whose mean of D is more than K_BLOCK standard errors (sigma's block RMS
  / B) from 0: noise averages out over a block, a wrong object, shadow or
  motion does not.
The noise reference is D_ref = E2 - E1 (same library, another seed). The
candidate passes when D_test = S2 - E1 (the same seeds, the other library)
is no worse than D_ref: MAD within MAD_SLACK, tail within TAIL_SLACK, biased
blocks at every block size within BLOCK_SLACK; and when the same-seed
difference S1 - E1 (Cycles is deterministic for a seed, so identical hits
give identical pixels) has a MAD no larger than D_ref's and no more biased
blocks than D_test is allowed. With
STATIC, the motion-blurred and static renders must differ by far more than
noise (the scene really exercises motion blur). Exit 1 when any check fails.
"""

import sys

import numpy as np

SIGMA_FLOOR = 1e-3
WINDOW = 5
K_SIGMA = 4.0
BLOCKS = (8, 16, 32)
K_BLOCK = 5.0
MAD_SLACK = 1.25  # D_test's MAD may be this factor above D_ref's
TAIL_SLACK = (1.5, 0.002)  # tail_test <= 1.5 tail_ref + 0.002
BLOCK_SLACK = (3, 0.0025)  # biased blocks: at most max(3, 0.25 %) more than D_ref
MOTION_FACTOR = 10  # STATIC - E1 must have this many times more biased blocks


def load(path):
    pixels = np.load(path)
    if pixels.ndim != 3 or pixels.shape[2] < 3:
        sys.exit(f"compare: {path} is not an HxWx(3|4) image")
    return pixels[..., :3].astype(np.float64)


def box_mean(a, size):
    """Mean over a size x size window, edges replicated, per channel."""
    pad = size // 2
    p = np.pad(a, ((pad, pad), (pad, pad), (0, 0)), mode="edge")
    c = np.cumsum(np.cumsum(p, axis=0), axis=1)
    c = np.pad(c, ((1, 0), (1, 0), (0, 0)))
    h, w = a.shape[:2]
    return (c[size:size + h, size:size + w] - c[:h, size:size + w]
            - c[size:size + h, :w] + c[:h, :w]) / (size * size)


def block_means(a, size):
    h, w = (a.shape[0] // size) * size, (a.shape[1] // size) * size
    a = a[:h, :w]
    return a.reshape(h // size, size, w // size, size, -1).mean(axis=(1, 3))


class Stats:
    def __init__(self, name, d, sigma):
        self.name = name
        self.mad = float(np.mean(np.abs(d)))
        self.max = float(np.max(np.abs(d)))
        self.tail = float(np.mean(np.abs(d) > K_SIGMA * sigma))
        self.blocks, self.n_blocks = [], []
        for size in BLOCKS:
            stderr = np.sqrt(block_means(sigma ** 2, size)) / size
            z = block_means(d, size) / stderr
            self.blocks.append(int(np.count_nonzero(np.abs(z) > K_BLOCK)))
            self.n_blocks.append(z.size)
        self.identical = float(np.mean(np.all(d == 0.0, axis=2)))

    def __str__(self):
        return (f"{self.name}: MAD {self.mad:.5f}, max {self.max:.4f}, beyond {K_SIGMA:g} sigma "
                f"{100 * self.tail:.3f}%, biased blocks "
                + ", ".join(f"{b}/{n} ({s}x{s})" for s, b, n in zip(BLOCKS, self.blocks, self.n_blocks))
                + ", "
                f"identical pixels {100 * self.identical:.1f}%")


def main():
    if len(sys.argv) not in (6, 7):
        sys.exit(__doc__)
    e1, e2, e3, s1, s2 = (load(p) for p in sys.argv[1:6])
    if not all(x.shape == e1.shape for x in (e2, e3, s1, s2)):
        sys.exit("compare: the renders have different sizes")
    sigma = np.maximum(np.sqrt(box_mean((e3 - e1) ** 2, WINDOW)), SIGMA_FLOOR)
    ref = Stats("noise reference   Embree seed 2 - Embree seed 1", e2 - e1, sigma)
    test = Stats("candidate         shim seed 2   - Embree seed 1", s2 - e1, sigma)
    same = Stats("same seed         shim seed 1   - Embree seed 1", s1 - e1, sigma)
    for s in (ref, test, same):
        print(s)
    failures = []
    if test.mad > MAD_SLACK * ref.mad:
        failures.append(f"MAD {test.mad:.5f} > {MAD_SLACK} x noise MAD {ref.mad:.5f}")
    if test.tail > TAIL_SLACK[0] * ref.tail + TAIL_SLACK[1]:
        failures.append(f"{100 * test.tail:.3f}% of pixel-channels beyond {K_SIGMA:g} sigma, "
                        f"noise reference {100 * ref.tail:.3f}%")
    for size, r, n, t, s in zip(BLOCKS, ref.blocks, ref.n_blocks, test.blocks, same.blocks):
        allowed = r + max(BLOCK_SLACK[0], int(BLOCK_SLACK[1] * n))
        for label, count in (("", t), ("same-seed: ", s)):
            if count > allowed:
                failures.append(f"{label}{count} biased {size}x{size} blocks, noise reference "
                                f"{r} (allowed {allowed})")
    if same.mad > ref.mad:
        failures.append(f"same-seed MAD {same.mad:.5f} exceeds the noise MAD {ref.mad:.5f}")
    if len(sys.argv) == 7:
        motion = Stats("motion blur off   Embree seed 1 - Embree seed 1 blurred", load(sys.argv[6]) - e1, sigma)
        print(motion)
        if motion.blocks[0] < MOTION_FACTOR * max(1, ref.blocks[0]):
            failures.append(f"motion blur barely changes the picture ({motion.blocks[0]} biased "
                            f"blocks): the scene does not exercise it")
    for f in failures:
        print("  FAIL " + f)
    print("compare: " + ("differs beyond sampling noise" if failures else "within sampling noise"))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
