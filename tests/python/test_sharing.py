"""Vertex steps are shared with numpy without a copy where the layout allows:
changing the array and calling rebuild() (or refit()) changes the hits."""
import numpy as np
import pytest

import mbrt
from conftest import moving_quad

RAY = np.array([[0.0, 0.0, -5.0, 0.0, 0.0, 1.0, 0.0, np.inf, 0.0]], dtype=np.float32)


@pytest.mark.parametrize("kind", ["stbvh", "bvh-interp", "msbvh", "mbkd", "fuzzykd", "brute"])
@pytest.mark.parametrize("update", ["rebuild", "refit"])
def test_changed_array_changes_hits_after_rebuild(kind, update):
    indices, steps = moving_quad(steps=2, offset=0.0)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps)
    assert scene.geometry(0)["shared"]
    accel = mbrt.Accel(scene, kind)
    assert accel.intersect(RAY).t[0] == pytest.approx(5.0)
    steps[:, :, 2] = 1.5  # the quad moves to z = 1.5, in place
    getattr(accel, update)()
    assert accel.intersect(RAY).t[0] == pytest.approx(6.5)
    steps[:, :, 0] += 10.0  # and away from the ray
    getattr(accel, update)()
    assert not accel.intersect(RAY).hit[0]


def test_one_step_of_many_is_shared():
    indices, steps = moving_quad(steps=3, offset=0.0)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps)
    accel = mbrt.Accel(scene, "stbvh")
    steps[2, :, 2] = 4.0  # only the last step moves: at time 1 the quad is at z = 4
    accel.rebuild()
    times = np.array([0.0, 0.5, 1.0], dtype=np.float32)
    rays = np.repeat(RAY, 3, axis=0)
    rays[:, 8] = times
    assert accel.intersect(rays).t == pytest.approx([5.0, 5.0, 9.0])


@pytest.mark.parametrize("make", [
    lambda s: s.astype(np.float64),             # another dtype
    lambda s: np.asfortranarray(s),             # coordinates not packed
    lambda s: np.concatenate([s, s], axis=2)[:, :, :3],  # vertices 24 bytes apart
])
def test_other_layouts_are_copied(make):
    indices, steps = moving_quad(steps=2, offset=0.0)
    array = make(steps)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, array)
    assert not scene.geometry(0)["shared"]
    accel = mbrt.Accel(scene, "stbvh")
    array[:, :, 2] = 3.0
    accel.rebuild()
    assert accel.intersect(RAY).t[0] == pytest.approx(5.0)  # the copy is what the scene reads


def test_share_false_copies():
    indices, steps = moving_quad(steps=2, offset=0.0)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps, share=False)
    assert not scene.geometry(0)["shared"]
    accel = mbrt.Accel(scene, "stbvh")
    steps[:, :, 2] = 3.0
    accel.rebuild()
    assert accel.intersect(RAY).t[0] == pytest.approx(5.0)


def test_scene_keeps_shared_array_alive():
    import gc
    indices, steps = moving_quad(steps=2, offset=0.0)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps)
    accel = mbrt.Accel(scene, "stbvh")
    del steps, scene
    gc.collect()
    np.zeros((1 << 16, 3), dtype=np.float32)  # reuse freed memory, if it were freed
    accel.rebuild()
    assert accel.intersect(RAY).t[0] == pytest.approx(5.0)
    assert accel.scene.num_geometries == 1


def test_added_geometry_needs_rebuild():
    indices, steps = moving_quad(steps=1, offset=0.0)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps[0])
    accel = mbrt.Accel(scene, "stbvh")
    closer = steps[0].copy()
    closer[:, 2] = -1.0
    scene.add_triangle_mesh(indices, closer)
    with pytest.raises(mbrt.Error, match="rebuild"):
        accel.intersect(RAY)
    accel.rebuild()
    hits = accel.intersect(RAY)
    assert hits.geom_id[0] == 1 and hits.t[0] == pytest.approx(4.0)


def test_intersect_into_an_earlier_result():
    indices, steps = moving_quad(steps=2, offset=0.0)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps)
    accel = mbrt.Accel(scene, "stbvh")
    rays = np.repeat(RAY, 3, axis=0)
    hits = accel.intersect(rays)
    t = hits.t
    rays[1, 2] = -7.0  # one ray starts farther away
    again = accel.intersect(rays, out=hits)
    assert again is hits and hits.t is t  # the same arrays, rewritten
    assert hits.t == pytest.approx([5.0, 7.0, 5.0])
    with pytest.raises(mbrt.Error, match="as many rays"):
        accel.intersect(rays[:2], out=hits)


def test_recycled_result_memory_never_aliases_a_live_result():
    # The result arrays of a dropped call are reused by the next one; any
    # array still held (even one field alone) keeps its memory to itself.
    indices, steps = moving_quad(steps=2, offset=0.0)
    scene = mbrt.Scene()
    scene.add_triangle_mesh(indices, steps)
    accel = mbrt.Accel(scene, "stbvh")
    near, far = np.repeat(RAY, 1000, axis=0), np.repeat(RAY, 1000, axis=0)
    far[:, 2] = -9.0
    kept_t = accel.intersect(near).t  # the Hits object is dropped, t is held
    kept = accel.intersect(near)
    del kept  # its memory goes to the next call
    for _ in range(3):
        again = accel.intersect(far)
        assert again.t == pytest.approx(np.full(1000, 9.0))
        assert again.ng.shape == (1000, 3) and again.ng.flags.writeable
        assert np.all(again.prim_id != 0xFFFFFFFF) and np.all(again.inst_id == 0xFFFFFFFF)
        assert kept_t == pytest.approx(np.full(1000, 5.0))
        del again
    empty = accel.intersect(np.zeros((0, 9), dtype=np.float32))
    assert len(empty) == 0 and empty.ng.shape == (0, 3)
