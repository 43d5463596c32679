"""Bad input raises mbrt.Error with the library's message, never crashes."""
import numpy as np
import pytest

import mbrt
from conftest import moving_quad


@pytest.fixture
def accel():
    scene = mbrt.Scene()
    scene.add_triangle_mesh(*moving_quad())
    return mbrt.Accel(scene, "stbvh")


def test_error_is_a_runtime_error():
    assert issubclass(mbrt.Error, RuntimeError)


def test_unknown_kind_lists_the_kinds():
    scene = mbrt.Scene()
    scene.add_triangle_mesh(*moving_quad())
    with pytest.raises(mbrt.Error, match=r"unknown accel kind 'nope' \(available: brute, .*stbvh"):
        mbrt.Accel(scene, "nope")


@pytest.mark.parametrize("options, message", [
    (dict(branching=3), "branching must be 2, 4 or 8"),
    (dict(max_leaf_size=0), "maxLeafSize"),
    (dict(frozen_time=2.0), "frozen time"),
    (dict(embree_mode="fast"), "embree_mode"),
])
def test_bad_build_options(options, message):
    scene = mbrt.Scene()
    scene.add_triangle_mesh(*moving_quad())
    with pytest.raises(mbrt.Error, match=message):
        mbrt.Accel(scene, "stbvh", **options)


def test_empty_scene():
    with pytest.raises(mbrt.Error, match="empty"):
        mbrt.Accel(mbrt.Scene(), "stbvh")


@pytest.mark.parametrize("indices, steps, message", [
    (np.array([[0, 1, 7]]), np.zeros((4, 3)), "uses vertex 7 but there are 4 vertices"),
    (np.array([[0, 1, -1]]), np.zeros((4, 3)), "negative"),
    (np.array([[0.0, 1.0, 2.0]]), np.zeros((4, 3)), "integer"),
    (np.array([0, 1, 2]), np.zeros((4, 3)), r"\(M, 3\)"),
    (np.array([[0, 1, 2]]), np.zeros((4, 2)), "last dimension must be 3"),
    (np.array([[0, 1, 2]]), np.zeros(12), r"\(S, N, 3\)"),
    (np.array([[0, 1, 2]]), np.full((4, 3), np.nan), "vertex 0 of step 0 is NaN"),
])
def test_bad_meshes(indices, steps, message):
    scene = mbrt.Scene()
    with pytest.raises(mbrt.Error, match=message):
        scene.add_triangle_mesh(indices, steps)
        mbrt.Accel(scene, "stbvh")


def test_bad_time_range():
    scene = mbrt.Scene()
    scene.add_triangle_mesh(*moving_quad(), time_range=(0.8, 0.2))
    with pytest.raises(mbrt.Error, match="time range"):
        mbrt.Accel(scene, "stbvh")


def test_bad_transforms():
    scene = mbrt.Scene()
    child = mbrt.Scene()
    child.add_triangle_mesh(*moving_quad())
    with pytest.raises(mbrt.Error, match="last row"):
        scene.add_instance(child, np.ones((4, 4)))
    with pytest.raises(mbrt.Error, match=r"\(S, 3, 4\)"):
        scene.add_instance(child, np.ones(5))
    scene.add_instance(child, np.zeros((3, 4)))  # singular
    with pytest.raises(mbrt.Error, match="singular"):
        mbrt.Accel(scene, "stbvh")


@pytest.mark.parametrize("call", [
    lambda a: a.intersect(np.zeros((4, 8), dtype=np.float32)),
    lambda a: a.intersect(),
    lambda a: a.intersect(org=np.zeros((4, 3))),
    lambda a: a.intersect(org=np.zeros((4, 3)), dir=np.ones((5, 3))),
    lambda a: a.intersect(org=np.zeros((4, 3)), dir=np.ones((4, 3)), time=np.zeros(3)),
    lambda a: a.intersect(np.zeros((4, 9)), org=np.zeros((4, 3))),
    lambda a: a.intersect(np.zeros((4, 9)), time=0.5),
    lambda a: a.occluded(np.zeros((4, 9, 1))),
])
def test_bad_ray_arrays(accel, call):
    with pytest.raises(mbrt.Error):
        call(accel)


def test_invalid_rays_miss_and_are_counted(accel):
    rays = np.zeros((3, 9), dtype=np.float32)
    rays[:, 5] = 1.0  # dir (0, 0, 1)
    rays[:, 2] = -5.0
    rays[:, 7] = np.inf
    rays[0, 8] = 1.5       # time outside [0, 1]
    rays[1, 3:6] = 0.0     # zero direction
    rays[2, 0] = np.nan    # NaN origin
    hits = accel.intersect(rays)
    assert not hits.hit.any()
    assert accel.stats()["invalid_rays"] == 3


def test_missing_file_names_it(tmp_path):
    path = str(tmp_path / "nothing.obj")
    with pytest.raises(mbrt.Error, match="nothing.obj"):
        mbrt.load(path)


def test_unknown_scene_and_integrator():
    with pytest.raises(mbrt.Error, match="unknown"):
        mbrt.scenes.make("nope")
    scene = mbrt.scenes.make("translate", size=0.005)
    with pytest.raises(mbrt.Error, match="integrator"):
        mbrt.render(scene, integrator="nope")


def test_render_with_accel_of_another_scene():
    a, b = mbrt.scenes.make("translate", size=0.005), mbrt.scenes.make("rotate", size=0.005)
    with pytest.raises(mbrt.Error, match="another scene"):
        mbrt.render(a, mbrt.Accel(b), width=8, height=8, spp=1)


def test_memory_budget():
    scene = mbrt.scenes.make("translate", size=0.01)
    with pytest.raises(mbrt.Error, match="budget"):
        mbrt.Accel(scene, "stbvh", memory_budget=1000)
