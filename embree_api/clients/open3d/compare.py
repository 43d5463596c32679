#!/usr/bin/python3
"""Compares two raycast.py outputs: REFERENCE (real Embree) and CANDIDATE.

    /usr/bin/python3 compare.py REFERENCE.npz CANDIDATE.npz

A ray agrees when both miss, or both hit the same geometry and primitive
with t, u, v and the normal equal within float tolerance. Every other ray
is a disagreement, checked in float64 (Moller-Trumbore on the two claimed
triangles):

- an *edge* disagreement is one where the nearer claimed hit lies within
  float32 precision of an edge of its triangle (EDGE_ULPS float32 ulps of
  the coordinates involved, measured as a distance in world units), or the
  two hits are at the same t (a shared edge or vertex): float32 cannot
  decide those, so they are tolerated and counted. The float64 reference says which side was right
  ("settled for reference/candidate") or that it cannot tell;
- the same primitive with t and the normal within tolerance but u, v
  apart by more than UV_TOL ("u/v settled"): float32 cannot compute u, v
  more precisely than about one ulp of the hit point's coordinates in the
  triangle's plane, which at grazing incidence (divided by |cos|) exceeds
  UV_TOL on small triangles. Tolerated when the float64 reference puts the
  candidate's u, v point no farther from the true one than the
  reference's, or than that ulp; which side is closer is counted;
- anything else (an interior hit missed, a false hit, the same primitive
  with different t/u/v/normal) is a real mismatch.

count_intersections may differ only on rays that pass within that
precision of an edge of some triangle (float64, over all triangles); test_occlusions only
where cast_rays had an edge disagreement or the ray passes near an edge.
Exit status 1 on any real mismatch, 0 otherwise.
"""

import sys

import numpy as np

INVALID = 0xFFFFFFFF
T_REL_TOL = 1e-5  # relative tolerance on t for the same primitive
UV_TOL = 1e-4  # absolute, barycentric
NORMAL_TOL = 1e-4  # absolute, on unit normals
EDGE_ULPS = 16  # distance to an edge, in float32 ulps, that float32 cannot settle
FLOAT32_EPS = float(np.finfo(np.float32).eps)
MAX_BRUTE_FORCE = 5000  # rays checked against all triangles in float64


def intersect64(org, d, v0, v1, v2):
    """Moller-Trumbore in float64 of one ray against triangles (k,3) each.

    Returns t, u, v (Embree's barycentrics: p = (1-u-v) v0 + u v1 + v v2),
    with nan where the ray is parallel to the triangle's plane."""
    e1, e2 = v1 - v0, v2 - v0
    p = np.cross(d, e2)
    det = np.einsum("ij,ij->i", e1, p)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.where(det != 0.0, 1.0 / det, np.nan)
        s = org - v0
        u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1)
        v = (q @ d) * inv
        t = np.einsum("ij,ij->i", e2, q) * inv
    return t, u, v


class Scene64:
    def __init__(self, data):
        self.vertices = []
        self.triangles = []
        i = 0
        while f"vertices_{i}" in data:
            self.vertices.append(data[f"vertices_{i}"].astype(np.float64))
            self.triangles.append(data[f"triangles_{i}"].astype(np.int64))
            i += 1

    def triangle(self, geom, prim):
        tri = self.triangles[geom][prim]
        return [self.vertices[geom][tri[k]] for k in range(3)]

    def hit(self, ray, geom, prim):
        """(t, signed distance to the nearest edge, tolerance), float64.

        The distance is in world units (negative: outside the triangle);
        the tolerance is what float32 can resolve at that point."""
        v0, v1, v2 = self.triangle(geom, prim)
        t, dist, tol = edge_distance(ray, v0[None], v1[None], v2[None])
        return float(t[0]), float(dist[0]), float(tol[0])

    def near_edge(self, ray):
        """True when the ray passes within float32 precision of an edge."""
        for vs, ts in zip(self.vertices, self.triangles):
            t, dist, tol = edge_distance(ray, vs[ts[:, 0]], vs[ts[:, 1]], vs[ts[:, 2]])
            if np.any((t > 0) & (np.abs(dist) <= tol)):
                return True
        return False


def edge_distance(ray, v0, v1, v2):
    """For triangles (k,3): t, the signed distance of the ray's float64 hit
    point on each triangle's plane to the triangle's nearest edge (each
    barycentric times the height onto the opposite edge), and the float32
    resolution there: EDGE_ULPS ulps of the largest coordinate involved."""
    org, d = ray[:3], ray[3:]
    t, u, v = intersect64(org, d, v0, v1, v2)
    twice_area = np.linalg.norm(np.cross(v1 - v0, v2 - v0), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        heights = [twice_area / np.linalg.norm(b - a, axis=1) for a, b in ((v1, v2), (v2, v0), (v0, v1))]
        dist = np.minimum(np.minimum((1.0 - u - v) * heights[0], u * heights[1]), v * heights[2])
    extent = np.max(np.abs(np.stack([v0, v1, v2])), axis=(0, 2))
    scale = np.abs(org).max() + np.abs(np.nan_to_num(t)) * np.abs(d).max() + extent
    return t, dist, EDGE_ULPS * FLOAT32_EPS * scale


def settle_uv(ray, scene, geom, prim, uv_ref, uv_cand):
    """For a same-primitive hit whose u, v differ beyond UV_TOL: whether the
    float64 reference settles it for the candidate -- its u, v point no
    farther from the true one than the reference's, or than one float32 ulp
    of the hit's coordinates seen in the triangle's plane (divided by |cos|
    of the incidence angle: grazing rays) -- and whether the candidate is
    the closer one."""
    v0, v1, v2 = scene.triangle(geom, prim)
    t, u, v = intersect64(ray[:3], ray[3:], v0[None], v1[None], v2[None])
    normal = np.cross(v1 - v0, v2 - v0)
    cos = abs(normal @ ray[3:]) / (np.linalg.norm(normal) * np.linalg.norm(ray[3:]))
    scale = np.abs(ray[:3]).max() + abs(t[0]) * np.abs(ray[3:]).max()
    ulp_in_plane = FLOAT32_EPS * scale / max(cos, 1e-12)

    def error(uv):  # world distance of the u, v point from the float64 one
        return np.linalg.norm((uv[0] - u[0]) * (v1 - v0) + (uv[1] - v[0]) * (v2 - v0))

    return error(uv_cand) <= max(error(uv_ref), ulp_in_plane), error(uv_cand) < error(uv_ref)


def compare_cast(ref, cand, scene, rays):
    """Returns (agree, edge, settled counts, real mismatch messages, edge rays)."""
    g_r, p_r = ref["geometry_ids"], ref["primitive_ids"]
    g_c, p_c = cand["geometry_ids"], cand["primitive_ids"]
    same_prim = (g_r == g_c) & (p_r == p_c)
    both_miss = same_prim & (g_r == INVALID)
    t_r, t_c = ref["t_hit"].astype(np.float64), cand["t_hit"].astype(np.float64)
    with np.errstate(invalid="ignore"):  # inf - inf on rays both miss
        close = np.abs(t_r - t_c) <= T_REL_TOL * np.maximum(1.0, np.abs(t_r))
    uv_close = np.all(np.abs(ref["primitive_uvs"] - cand["primitive_uvs"]) <= UV_TOL, axis=1)
    n_close = np.all(np.abs(ref["primitive_normals"] - cand["primitive_normals"]) <= NORMAL_TOL, axis=1)
    agree = both_miss | (same_prim & close & uv_close & n_close)
    real, edge_rays = [], set()
    settled = {"reference": 0, "candidate": 0, "undecided": 0, "uv": 0, "uv_candidate_closer": 0}
    for i in np.flatnonzero(same_prim & ~both_miss & ~agree):
        if close[i] and n_close[i]:
            verdict = settle_uv(rays[i].astype(np.float64), scene, g_r[i], p_r[i],
                                ref["primitive_uvs"][i].astype(np.float64),
                                cand["primitive_uvs"][i].astype(np.float64))
            if verdict[0]:
                settled["uv"] += 1
                settled["uv_candidate_closer"] += int(verdict[1])
                continue
        real.append(f"ray {i}: same primitive ({g_r[i]},{p_r[i]}) but t {t_r[i]!r} vs {t_c[i]!r}, "
                    f"uv {ref['primitive_uvs'][i]} vs {cand['primitive_uvs'][i]}, "
                    f"normal {ref['primitive_normals'][i]} vs {cand['primitive_normals'][i]}")
    differing = np.flatnonzero(~same_prim)
    if len(differing) > MAX_BRUTE_FORCE:
        real.append(f"{len(differing)} rays hit different primitives (more than "
                    f"{MAX_BRUTE_FORCE}: not settled one by one)")
        return int(agree.sum()), 0, settled, real, edge_rays
    for i in differing:
        ray = rays[i].astype(np.float64)
        claims = []  # (side, t, distance to the nearest edge, its tolerance), float64
        for side, g, p in (("reference", g_r[i], p_r[i]), ("candidate", g_c[i], p_c[i])):
            if g != INVALID:
                claims.append((side,) + scene.hit(ray, g, p))
        bad = [c for c in claims if c[2] < -c[3] or not c[1] >= 0]
        if bad:
            real.append(f"ray {i}: {bad[0][0]} reports a hit that float64 puts outside its "
                        f"triangle (t {bad[0][1]:.9g}, {-bad[0][2]:.3g} outside its edge, "
                        f"float32 resolves {bad[0][3]:.3g})")
            continue
        nearest = min(claims, key=lambda c: c[1])
        at_same_t = len(claims) == 2 and abs(claims[0][1] - claims[1][1]) <= T_REL_TOL * max(1.0, nearest[1])
        other = "candidate" if nearest[0] == "reference" else "reference"
        if at_same_t or nearest[2] <= nearest[3]:
            edge_rays.add(int(i))
            if at_same_t or nearest[2] == 0.0:
                settled["undecided"] += 1  # both answers are right
            elif nearest[2] > 0.0:
                settled[nearest[0]] += 1  # float64: the nearer hit is real
            else:
                settled[other] += 1  # float64: the nearer hit is just outside
        else:
            real.append(f"ray {i}: {other} misses the hit on {nearest[0]}'s primitive at t "
                        f"{nearest[1]:.9g}, {nearest[2]:.3g} inside its edges (reference "
                        f"({g_r[i]},{p_r[i]}), candidate ({g_c[i]},{p_c[i]}))")
    return int(agree.sum()), len(edge_rays), settled, real, edge_rays


def compare_per_ray(name, a, b, scene, rays, tolerated):
    """Per-ray integer results that may differ only on edge rays."""
    differing = np.flatnonzero(a != b)
    if len(differing) > MAX_BRUTE_FORCE:
        return 0, [f"{name}: {len(differing)} rays differ (more than {MAX_BRUTE_FORCE})"]
    real, edge = [], 0
    for i in differing:
        if int(i) in tolerated or scene.near_edge(rays[i].astype(np.float64)):
            edge += 1
        else:
            real.append(f"{name}: ray {i}: reference {a[i]}, candidate {b[i]}, and the ray "
                        f"passes no edge within float32 precision (float64 check)")
    return edge, real


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    ref, cand = np.load(sys.argv[1]), np.load(sys.argv[2])
    rays = ref["rays"]
    if not np.array_equal(rays, cand["rays"]):
        sys.exit("compare: the two runs traced different rays")
    scene = Scene64(ref)
    n = len(rays)
    agree, edge, settled, real, edge_rays = compare_cast(ref, cand, scene, rays)
    print(f"cast_rays: {n} rays, {agree} agree, {edge} edge disagreements tolerated "
          f"(float64 settles {settled['reference']} for the reference, {settled['candidate']} "
          f"for the candidate, {settled['undecided']} undecidable), {settled['uv']} same-primitive u/v "
          f"differences settled by float64 (the candidate closer on "
          f"{settled['uv_candidate_closer']}), {len(real)} real mismatches")
    count_edge, count_real = compare_per_ray("count_intersections", ref["counts"], cand["counts"],
                                             scene, rays, edge_rays)
    print(f"count_intersections: {int(np.count_nonzero(ref['counts'] == cand['counts']))} equal, "
          f"{count_edge} differ on edge rays, {len(count_real)} real mismatches")
    occl_edge, occl_real = compare_per_ray("test_occlusions", ref["occluded"], cand["occluded"],
                                           scene, rays, edge_rays)
    print(f"test_occlusions: {int(np.count_nonzero(ref['occluded'] == cand['occluded']))} equal, "
          f"{occl_edge} differ on edge rays, {len(occl_real)} real mismatches")
    real += count_real + occl_real
    ref_hits = int(np.count_nonzero(ref["geometry_ids"] != INVALID))
    cand_hits = int(np.count_nonzero(cand["geometry_ids"] != INVALID))
    if ref_hits == 0 and cand_hits > 0:
        print("compare: the reference hits nothing but the candidate does: the rays carry "
              "mask 0, so the candidate seems to ignore ray masks")
    for line in real[:20]:
        print("  MISMATCH " + line)
    if len(real) > 20:
        print(f"  ... and {len(real) - 20} more")
    sys.exit(1 if real else 0)


if __name__ == "__main__":
    main()
