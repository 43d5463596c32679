"""Loaders, the scene suite, render, bench, stats, and the ray file layout
shared with `mbrt trace`."""
import subprocess

import numpy as np
import pytest

import mbrt
from conftest import random_rays

QUAD_OBJ = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n"


def test_load_obj_and_procedural_motion(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text(QUAD_OBJ)
    scene = mbrt.load(str(path))
    assert scene.num_primitives == 2 and scene.geometry(0)["steps"] == 1
    ray = np.array([[0.5, 0.5, -3, 0, 0, 1, 0, np.inf, 0.5]], dtype=np.float32)
    assert mbrt.Accel(scene).intersect(ray).t[0] == pytest.approx(3.0)
    moving = mbrt.load(str(path), motion="translate:5,0,0")
    assert moving.geometry(0)["steps"] >= 2


def test_load_builtin_name_with_size():
    scene = mbrt.load("hairball", size=0.005)
    assert scene.name == "hairball" and scene.num_primitives > 0


def test_load_gltf_shutter_and_steps():
    import pathlib
    path = pathlib.Path(__file__).resolve().parents[2].parent / "shared" / "scenes" / "cesium_man" / "CesiumMan.glb"
    if not path.exists():
        pytest.skip(f"{path} is absent")
    scene = mbrt.load(str(path), shutter=(0.0, 0.5), steps=4)
    assert any(scene.geometry(g)["steps"] == 4 for g in range(scene.num_geometries))
    with pytest.raises(mbrt.Error):
        mbrt.load(str(path), steps=0)


def test_scene_suite():
    names = mbrt.scenes.names()
    assert names[:3] == ["translate", "rotate", "crowd"]
    for name in names:
        scene = mbrt.scenes.make(name, size=0.003)
        assert scene.name == name and len(scene) > 0


def test_stats_dict():
    scene = mbrt.scenes.make("crowd", size=0.005)
    stats = mbrt.Accel(scene, "msbvh").stats()
    assert stats["kind"] == "msbvh"
    assert stats["primitives"] >= scene.num_primitives  # all levels
    assert stats["bytes"] > 0 and stats["leaf_nodes"] > 0 and stats["references"] >= stats["primitives"]
    assert set(stats) >= {"inner_nodes", "max_depth", "peak_build_bytes", "sah_cost", "build_seconds", "invalid_rays"}
    assert stats["leaf_block_bytes"] == 0  # msbvh tests its triangles one at a time
    blocked = mbrt.Accel(scene, "bvh-interp").stats()
    assert 0 < blocked["leaf_block_bytes"] < blocked["bytes"]


def test_render_shape_and_determinism():
    scene = mbrt.scenes.make("demo", size=0.005)
    accel = mbrt.Accel(scene, "stbvh")
    a = mbrt.render(scene, accel, width=24, height=16, spp=2, integrator="normals")
    b = mbrt.render(scene, width=24, height=16, spp=2, integrator="normals")  # its own accel
    assert a.shape == (16, 24, 3) and a.dtype == np.float32
    assert np.array_equal(a, b)
    assert a.max() > 0.1  # the camera sees the scene
    ao = mbrt.render(scene, accel, width=24, height=16, spp=2, integrator="ao", tonemap=True)
    assert ao.shape == (16, 24, 3) and np.isfinite(ao).all()


def test_render_python_scene_is_framed():
    from conftest import moving_quad
    scene = mbrt.Scene()
    scene.add_triangle_mesh(*moving_quad())
    image = mbrt.render(scene, width=16, height=16, spp=1, integrator="normals")
    assert 0.05 < (image.sum(axis=2) > 0).mean() < 1.0


def test_bench_table():
    rows = mbrt.bench(["translate"], ["stbvh", "brute"], quick=True, size=0.002, width=16, height=16,
                      repeats=1, frozen_times=2, brute_sample=200)
    assert [r["accel"] for r in rows] == ["stbvh", "brute"]
    row = rows[0]
    assert row["scene"] == "translate" and row["secondary_mrays_mt"] > 0 and row["bytes"] > 0
    assert row["secondary_mismatches_brute"] == 0 and row["secondary_brute_checked"] > 0
    assert row["mismatches"] == 0


def test_bench_on_a_python_scene():
    from conftest import mixed_scene
    scene = mixed_scene(np.random.default_rng(1))
    rows = mbrt.bench([scene], ["bvh-interp"], quick=True, width=16, height=16, repeats=1, frozen_times=2,
                      brute_sample=200)
    assert rows[0]["scene"] == "python" and rows[0]["mismatches"] == 0


def test_ray_file_round_trip_matches_mbrt_trace(tmp_path, cli):
    scene = mbrt.scenes.make("crowd", size=0.005)
    rays = random_rays(np.random.default_rng(2), 3000, scene.bounds())
    mbrt.write_rays(str(tmp_path / "rays.bin"), rays)
    assert np.array_equal(mbrt.read_rays(str(tmp_path / "rays.bin")), rays)
    subprocess.run([cli, "trace", "crowd", "--size", "0.005", "--accel", "stbvh", "--rays",
                    str(tmp_path / "rays.bin"), "--hits", str(tmp_path / "hits.bin")], check=True,
                   stdout=subprocess.DEVNULL)
    records = np.fromfile(tmp_path / "hits.bin", dtype=[("t", "<f4"), ("geom", "<u4"), ("prim", "<u4")])
    hits = mbrt.Accel(scene, "stbvh").intersect(rays)
    assert np.array_equal(records["t"], hits.t)
    assert np.array_equal(records["geom"], hits.geom_id) and np.array_equal(records["prim"], hits.prim_id)
