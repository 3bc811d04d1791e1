"""`mechfmu run SCENE --animate FILE.gif`: the bodies drawn to scale from their recorded
attitude, the frames written with their time labels, and one clear line for what cannot
be animated."""

import numpy as np
import pytest

from assemblies.assembly import AssemblyError
from assemblies.run import run_scene_full
from assemblies.scenes import scene
from assemblies.scenes.animate import (DRAWERS, animate, animation_record, bodies,
                                       box_dimensions, check_animation_file,
                                       ffmpeg_executable, frame_indices)


def _poses(name):
    sc = scene(name)
    from dataclasses import replace
    run = run_scene_full(replace(sc, record=animation_record(sc)), plot=False)
    asm = run.result.assembly
    return run.result, asm, {n: drawer(run.result, n, comp)
                             for n, (comp, _, drawer) in bodies(asm).items()}


def test_box_of_the_same_moments_has_them():
    """Edges a, b, c of a uniform box: I_x = m (b^2 + c^2) / 12, cyclically."""
    a, b, c, m = 0.4, 0.3, 0.2, 2.0
    moments = (m * (b**2 + c**2) / 12, m * (c**2 + a**2) / 12, m * (a**2 + b**2) / 12)
    np.testing.assert_allclose(box_dimensions(moments, m), [a, b, c], rtol=1e-12)


def test_disk_is_drawn_to_scale_and_turns_rigidly():
    """wobble_exercise: I_s = 0.25 kg.m2 is a 1 kg disk of radius 2 sqrt(I_s) = 1 m; every
    rim point stays 1 m from the centre and the rim stays normal to the drawn axis."""
    result, _, poses = _poses("wobble_exercise")
    rim, _, axis = poses["disk"].outlines
    np.testing.assert_allclose(np.linalg.norm(rim, axis=2), 1.0, rtol=1e-12)
    n = axis[:, 1] / np.linalg.norm(axis[:, 1], axis=1)[:, None]
    assert np.abs(np.einsum("nki,ni->nk", rim, n)).max() < 1e-12
    # the drawn axis is the recorded n
    recorded = np.column_stack([result[f"disk.n_{a}"] for a in "XYZ"])
    np.testing.assert_allclose(n, recorded, atol=1e-12)


def test_string_body_box_keeps_its_edges_and_hangs_from_its_string():
    result, asm, poses = _poses("string_body")
    pose = poses["body"]
    p = asm.component("body").values
    dims = box_dimensions((p["I_xx"], p["I_yy"], p["I_zz"]), p["m"])
    low = pose.outlines[0]  # the face z = -c/2: edges a, b, a, b
    edges = np.linalg.norm(np.diff(low, axis=1), axis=2)
    np.testing.assert_allclose(edges, np.tile([dims[0], dims[1]] * 2, (len(low), 1)),
                               rtol=1e-9)
    string = pose.lines[0]
    np.testing.assert_allclose(string[:, 0], 0.0)  # from the support
    np.testing.assert_allclose(np.linalg.norm(string[:, 1], axis=1), result["body.l"],
                               rtol=1e-12)


def test_gif_has_the_frames_asked_and_their_times(tmp_path):
    from PIL import Image
    result, asm, _ = _poses("wobble_exercise")
    path = tmp_path / "disk.gif"
    labels = animate(result, asm, path, "wobble", frames=4, fps=5)
    t = result["time"]
    assert labels == [f"t = {t[i]:.2f} s" for i in frame_indices(len(t), 4)]
    assert labels[0] == "t = 0.00 s" and labels[-1] == f"t = {t[-1]:.2f} s"
    with Image.open(path) as image:
        assert image.n_frames == 4
        frames = []
        for k in range(image.n_frames):
            image.seek(k)
            frames.append(np.asarray(image.convert("L"), dtype=float))
    # the body moves between frames: the pictures differ
    assert np.abs(frames[1] - frames[0]).max() > 0


def test_mp4_has_the_frames_asked_and_they_move(tmp_path):
    """Needs an ffmpeg: on the PATH or from the optional imageio-ffmpeg wheel
    (pip install 'mechfmu[animate]'); skipped where there is neither."""
    import subprocess
    exe = ffmpeg_executable()
    if exe is None:
        pytest.skip("no ffmpeg on the PATH and no imageio-ffmpeg")
    result, asm, _ = _poses("wobble_exercise")
    path = tmp_path / "disk.mp4"
    labels = animate(result, asm, path, "wobble", frames=4, fps=5)
    assert len(labels) == 4
    assert path.read_bytes()[4:8] == b"ftyp"  # an ISO media file
    # decoded back by ffmpeg itself: 6 x 6 in at 80 dpi, one grey byte a pixel
    raw = subprocess.run([exe, "-v", "error", "-i", str(path), "-f", "rawvideo", "-pix_fmt",
                          "gray", "-"], capture_output=True, check=True).stdout
    frames = np.frombuffer(raw, dtype=np.uint8).reshape(-1, 480, 480).astype(float)
    assert len(frames) == 4
    assert np.abs(frames[1] - frames[0]).max() > 0


def test_every_drawer_names_outputs_its_component_has():
    import components
    for cls_name, (needs, _) in DRAWERS.items():
        fm = components.flatten(getattr(components, cls_name)())
        names = {v.name for v in (*fm.states, *fm.outputs)}
        assert set(needs) <= names, (cls_name, set(needs) - names)


def test_what_cannot_be_animated_says_so_in_one_line(tmp_path):
    with pytest.raises(AssemblyError, match="no body to animate"):
        animation_record(scene("stick_slip"))
    with pytest.raises(AssemblyError, match=r"\.gif or \.mp4"):
        check_animation_file(tmp_path / "x.avi")
    with pytest.raises(AssemblyError, match="does not exist"):
        check_animation_file(tmp_path / "missing" / "x.gif")


def test_command_line_mp4_without_ffmpeg_or_other_scene_fails_cleanly(tmp_path, capsys,
                                                                     monkeypatch):
    from assemblies.cli import main
    import shutil
    import sys
    monkeypatch.setattr(shutil, "which", lambda name: None)
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # nor the wheel's: ImportError
    assert main(["run", "string_body", "--out", str(tmp_path),
                 "--animate", str(tmp_path / "x.mp4")]) == 2
    err = capsys.readouterr().err
    assert "ffmpeg" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_cone_touches_its_incline_and_keeps_its_apex():
    """The drawn cone rests on the plane z = 0: its base circle's lowest point (centre c,
    axis a from the apex: c_z - R sqrt(1 - a_z^2)) is on it at every frame, nothing of
    it is below, the apex stays at the origin and every slant is h long."""
    _, asm, poses = _poses("cone_incline")
    p = asm.component("cone").values
    rim, *slants = poses["cone"].outlines
    centre = rim[:, :-1].mean(axis=1)
    a = centre / np.linalg.norm(centre, axis=1)[:, None]
    np.testing.assert_allclose(centre[:, 2] - p["R"] * np.sqrt(1 - a[:, 2] ** 2), 0.0,
                               atol=1e-12)
    assert rim[:, :, 2].min() > -1e-12
    for s in slants:
        np.testing.assert_allclose(s[:, 0], 0.0, atol=1e-15)
        np.testing.assert_allclose(np.linalg.norm(s[:, 1], axis=1), p["h"], rtol=1e-12)
