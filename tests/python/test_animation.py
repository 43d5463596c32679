"""Documents and their frames (mbrt.load(...).frames(...), docs/python.md):
the input loaded once, the frames' scene updated in place, the accel that
follows it checked against brute force on every frame."""
import numpy as np
import pytest

import mbrt
from conftest import ROOT, assert_agrees, random_rays

CESIUM = ROOT.parent / "shared" / "scenes" / "cesium_man" / "CesiumMan.glb"


def test_document_is_a_scene_with_a_timeline():
    doc = mbrt.load("skinned", size=0.02)
    assert isinstance(doc, mbrt.Document) and isinstance(doc, mbrt.Scene)
    assert doc.num_geometries > 0 and doc.name == "skinned"
    t = doc.timeline
    assert (t.start, t.end, t.what) == (0.0, 1.0, "motion over one second")
    assert doc.frame_range() == range(0, 24)
    assert doc.frame_range(fps=12, shutter_angle=360) == range(0, 12)
    assert mbrt.Accel(doc, "bvh-interp").kind == "bvh-interp"  # the document's own scene


def test_frames_update_in_place_and_the_accel_follows(rng):
    doc = mbrt.load("skinned", size=0.02)
    frames = doc.frames(frames=[0, 5, 11, 23], accel="bvh-interp", update="refit")
    assert len(frames) == 4
    scene = accel = None
    for frame in frames:
        if scene is None:
            scene, accel = frame.scene, frame.accel
            assert frame.change == "layout" and frame.update["what"] == "build"
        else:
            assert frame.scene is scene and frame.accel is accel  # the same objects, updated
            assert frame.change == "vertices"
            assert frame.update["what"] == "refit" and frame.update["refitted"]
        assert frame.shutter == pytest.approx((frame.index / 24, frame.index / 24 + 1 / 48))
        assert frame.scene_seconds >= 0 and frame.update["seconds"] >= 0
        rays = random_rays(rng, 1500, scene.bounds())
        assert assert_agrees(mbrt.Accel(scene, "brute"), accel, rays, label=f"frame {frame.index}") > 50
    assert len(frames) == 0


def test_a_frame_is_the_scene_loaded_over_its_shutter():
    doc = mbrt.load("skinned", size=0.02)
    frame = next(iter(doc.frames(frames=[7], accel="msbvh")))
    loaded = mbrt.load("skinned", size=0.02, shutter=frame.shutter)
    a = mbrt.render(frame.scene, frame.accel, width=48, height=32, spp=1, integrator="normals")
    b = mbrt.render(loaded, width=48, height=32, spp=1, integrator="normals")
    assert np.abs(a - b).max(axis=2).__gt__(1 / 255).sum() <= 2  # ties only
    first = mbrt.render(mbrt.load("skinned", size=0.02, shutter=(0.0, 1 / 48)), width=48, height=32, spp=1,
                        integrator="normals")
    assert np.abs(a - first).max() > 0.1  # frame 7 is not frame 0


def test_an_accel_of_an_old_frame_refuses_to_trace(rng):
    doc = mbrt.load("skinned", size=0.02)
    frames = iter(doc.frames(frames=[0, 1]))
    frame = next(frames)
    assert frame.accel is None and frame.update is None
    mine = mbrt.Accel(frame.scene, "bvh-interp")
    rays = random_rays(rng, 100, frame.scene.bounds())
    mine.intersect(rays)
    next(frames)
    with pytest.raises(mbrt.Error, match="another frame"):
        mine.intersect(rays)
    assert mine.refit() is True
    assert_agrees(mbrt.Accel(frame.scene, "brute"), mine, rays, label="refitted by hand")


def test_instances_change_the_layout_and_the_accel_is_rebuilt(rng):
    doc = mbrt.load("demo", size=0.05)
    whats = []
    for frame in doc.frames(frames=[0, 12], accel="msbvh", update="auto"):
        assert frame.change == "layout"
        whats.append(frame.update["what"])
        assert frame.update["sah_cost"] > 0
        assert_agrees(mbrt.Accel(frame.scene, "brute"), frame.accel, random_rays(rng, 800, frame.scene.bounds()))
    assert whats == ["build", "rebuild (new layout)"]


def test_bad_frames_and_options_raise_before_any_work(tmp_path):
    doc = mbrt.load("skinned", size=0.02)
    with pytest.raises(mbrt.Error, match="frames 0 to 23 at 24 fps"):
        doc.frames(frames=[3, 24])
    with pytest.raises(mbrt.Error, match="frame rate"):
        doc.frame_range(fps=0)
    with pytest.raises(mbrt.Error, match="update must be"):
        doc.frames(accel="bvh-interp", update="sometimes")
    with pytest.raises(mbrt.Error, match="unknown accel kind"):
        doc.frames(accel="octree")
    with pytest.raises(mbrt.Error, match="rebuild factor"):
        doc.frames(accel="bvh-interp", rebuild_factor=0.5)
    with pytest.raises(mbrt.Error, match="outside the timeline"):
        mbrt.load("skinned", size=0.02, shutter=(0.5, 1.5))
    scene_file = ROOT / "tests" / "data" / "cube_scene.json"
    json_doc = mbrt.load(str(scene_file))
    assert json_doc.num_geometries > 0
    with pytest.raises(mbrt.Error, match="JSON scene file"):
        json_doc.timeline
    with pytest.raises(mbrt.Error, match="JSON scene file"):
        json_doc.frames()


def test_obj_sequence_keys_are_seconds():
    doc = mbrt.load(str(ROOT / "tests" / "data" / "keys"), fps=4)
    assert doc.timeline.what == "2 keys at 4 fps" and doc.timeline.end == 0.25
    assert doc.frame_range(fps=4) == range(0, 1)
    assert doc.geometry(0)["steps"] == 2  # the document: the whole timeline


def test_gltf_frames_are_the_clip_loaded_over_their_shutters():
    if not CESIUM.exists():
        pytest.skip(f"{CESIUM} is absent")
    doc = mbrt.load(str(CESIUM), stage=True)
    assert doc.timeline.what == "clip 0" and doc.timeline.end == pytest.approx(2.0)
    assert doc.num_geometries == 2  # the model and its ground
    for frame in doc.frames(frames=[0, 30]):
        loaded = mbrt.load(str(CESIUM), shutter=frame.shutter, stage=True)
        for g in range(loaded.num_geometries):
            assert frame.scene.geometry(g) == loaded.geometry(g)
