"""3-D animations of the body scenes from their recorded attitude (seed 8.6, exercises 3
and 5 ask for them): `mechfmu run SCENE --animate FILE.gif|mp4`.

Each body component that can be drawn has a drawer here: the outputs it needs recorded
and, from a run, its outline fixed in the body and carried through the recorded attitude
into ground axes at every output time (drawn to scale: the coin's and the disks' radii,
the axle body's and the string body's boxes of the same mass and principal moments), a
point whose path is traced, and lines fixed in the ground or joining the body to it (the
axle, the string). Any scene whose assembly holds such a body can be animated.
"""
from __future__ import annotations

import math
import shutil
import textwrap
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..assembly import AssemblyError
from ..plot import pyplot
from ..result import Result
from .bodies_seed import _rot_x, _rot_z, disk_attitude

CIRCLE = 48  # points on a drawn circle: smooth at the sizes drawn
FRAMES = 80  # frames at most: the run's outputs are sampled evenly down to this (3-D
             # frames take ~0.3 s each to draw)
FPS = 20


@dataclass
class Pose:
    """One body through a run, in ground axes: `outlines` are polylines fixed in the body,
    each (n_t, k, 3); `path` (n_t, 3) the point whose trace is drawn; `lines` (n_t, 2, 3)
    segments such as an axle or a string; `size` the body's largest dimension [m]."""
    outlines: list[np.ndarray]
    path: np.ndarray
    size: float
    lines: list[np.ndarray] = field(default_factory=list)


def _carry(R: np.ndarray, origin: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Body points (k, 3) placed by rotations R (n, 3, 3) about origins (n, 3)."""
    return origin[:, None, :] + np.einsum("nij,kj->nki", R, points)


def circle(radius: float, axis: int) -> np.ndarray:
    """A closed circle of `radius` about body axis `axis` (0, 1, 2), through the origin."""
    u = np.linspace(0.0, 2 * math.pi, CIRCLE + 1)
    a, b = [k for k in range(3) if k != axis]
    points = np.zeros((CIRCLE + 1, 3))
    points[:, a], points[:, b] = radius * np.cos(u), radius * np.sin(u)
    return points


def box_dimensions(moments, m: float) -> np.ndarray:
    """Edges of the uniform box with mass m and principal moments (I_1, I_2, I_3):
    I_1 = m (b^2 + c^2) / 12 and cyclically, so a^2 = 6 (I_2 + I_3 - I_1) / m."""
    I1, I2, I3 = moments
    squares = 6 / m * np.array([I2 + I3 - I1, I3 + I1 - I2, I1 + I2 - I3])
    return np.sqrt(np.maximum(squares, 0.0))


def box_edges(dims) -> list[np.ndarray]:
    """The 12 edges of a box centred on the origin as four polylines: two faces and the
    two pairs of edges between them."""
    a, b, c = np.asarray(dims) / 2
    face = np.array([[-a, -b], [a, -b], [a, b], [-a, b], [-a, -b]])
    low = np.column_stack([face, np.full(5, -c)])
    high = np.column_stack([face, np.full(5, c)])
    joins = [np.array([low[k], high[k], high[k + 1], low[k + 1]]) for k in (0, 2)]
    return [low, high, *joins]


def _principal_outline(moments, m: float) -> tuple[list[np.ndarray], float]:
    """The body as drawn from its principal moments: a flat disk when two are equal and
    the third their sum (radius 2 sqrt(I_d / m)), else the box with the same moments."""
    moments = np.asarray(moments, dtype=float)
    order = np.argsort(moments)
    small, middle, large = moments[order]
    if math.isclose(small, middle, rel_tol=1e-9) and math.isclose(large, small + middle,
                                                                  rel_tol=1e-9):
        radius = 2 * math.sqrt(small / m)
        rim = circle(radius, int(order[2]))
        spoke = np.zeros((2, 3))
        spoke[1, [k for k in range(3) if k != order[2]][0]] = radius
        return [rim, spoke], 2 * radius
    dims = box_dimensions(moments, m)
    return box_edges(dims), float(dims.max())


# --- the drawers, one per body component ------------------------------------------
def _disk(result: Result, name: str, component) -> Pose:
    """WobblingDisk: the disk in its y-z plane (axis x), I_s = m r^2 / 4 for 1 kg, a spoke
    to show the spin, its axis n; the centre is held still, the axis tip traced."""
    radius = 2 * math.sqrt(component.values["I_s"])
    R, _ = disk_attitude(*(result[f"{name}.{k}"] for k in
                           ("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot")))
    origin = np.zeros((len(R), 3))
    spoke = np.array([[0.0, 0.0, 0.0], [0.0, radius, 0.0]])
    axis = np.array([[0.0, 0.0, 0.0], [radius, 0.0, 0.0]])
    outlines = [_carry(R, origin, p) for p in (circle(radius, 0), spoke, axis)]
    return Pose(outlines, outlines[2][:, 1], 2 * radius)


def _coin(result: Result, name: str, component) -> Pose:
    """RollingCoin: (3,1,3) angles R3(phi) R1(theta) R3(psi), the coin's face in its body
    x-y plane, centre (x, y, R sin(theta)); the contact point's path on the ground."""
    radius = component.values["R"]
    phi, theta, psi = (result[f"{name}.{k}"] for k in ("phi", "theta", "psi"))
    R = _rot_z(phi) @ _rot_x(theta) @ _rot_z(psi)
    centre = np.column_stack([result[f"{name}.x"], result[f"{name}.y"],
                              radius * np.sin(theta)])
    spoke = np.array([[0.0, 0.0, 0.0], [radius, 0.0, 0.0]])
    outlines = [_carry(R, centre, p) for p in (circle(radius, 2), spoke)]
    contact = np.column_stack([result[f"{name}.x_C"], result[f"{name}.y_C"],
                               np.zeros(len(phi))])
    return Pose(outlines, contact, 2 * radius)


def quaternion_matrices(q0, q1, q2, q3) -> np.ndarray:
    """Rotation matrices (n, 3, 3) of quaternions, divided by |q|^2 as the models do."""
    n = q0**2 + q1**2 + q2**2 + q3**2
    rows = [[q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
            [2 * (q1 * q2 + q0 * q3), q0**2 - q1**2 + q2**2 - q3**2, 2 * (q2 * q3 - q0 * q1)],
            [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), q0**2 - q1**2 - q2**2 + q3**2]]
    return np.stack([np.stack(row, -1) for row in rows], -2) / n[:, None, None]


def _quaternion_body(result: Result, name: str, component) -> Pose:
    """TorqueFreeBody, NutationDamperBody: the box of their principal moments (1 kg: they
    carry no mass), G held still; the tip of its body x axis traced."""
    p = component.values
    R = quaternion_matrices(*(result[f"{name}.q{k}"] for k in range(4)))
    outline, size = _principal_outline((p["I_xx"], p["I_yy"], p["I_zz"]), 1.0)
    origin = np.zeros((len(R), 3))
    axis = _carry(R, origin, np.array([[0.0, 0.0, 0.0], [size, 0.0, 0.0]]))
    return Pose([_carry(R, origin, o) for o in outline] + [axis], axis[:, 1], size)


def _string_body(result: Result, name: str, component) -> Pose:
    """RigidBodyOnString: the box of its mass and moments at G, the string from the
    support O to B; G's path traced."""
    p = component.values
    R = np.stack([np.column_stack([result[f"{name}.{b}_{a}"] for a in "XYZ"])
                  for b in "xyz"], axis=-1)
    G = np.column_stack([result[f"{name}.{k}"] for k in "xyz"])
    outline, size = _principal_outline((p["I_xx"], p["I_yy"], p["I_zz"]), p["m"])
    B = np.column_stack([result[f"{name}.B_{a}"] for a in "XYZ"])
    string = np.stack([np.zeros_like(B), B], axis=1)
    return Pose([_carry(R, G, o) for o in outline], G, size, [string])


def _axle_body(result: Result, name: str, component) -> Pose:
    """RigidBodyOnAxle: the body (disk or box of its principal moments, principal axes
    from I_cm) turned by R(n, theta) about P at the origin, the axle through P; G traced."""
    from components.bodies.axle import _INERTIA
    p = component.values
    I_xx, I_yy, I_zz, I_xy, I_xz, I_yz = (p[k] for k in _INERTIA)
    moments, axes = np.linalg.eigh(np.array([[I_xx, I_xy, I_xz], [I_xy, I_yy, I_yz],
                                             [I_xz, I_yz, I_zz]]))
    outline, size = _principal_outline(moments, p["m"])
    n = np.array([p["n_x"], p["n_y"], p["n_z"]])
    n /= np.linalg.norm(n)
    theta = result[f"{name}.theta"]
    N = np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    c, s = np.cos(theta)[:, None, None], np.sin(theta)[:, None, None]
    turn = c * np.eye(3) + s * N + (1 - c) * np.outer(n, n)  # Rodrigues
    r = np.array([p["r_x"], p["r_y"], p["r_z"]])
    G = turn @ r
    R = turn @ axes
    reach = np.linalg.norm(r) + size
    axle = np.tile(np.array([-reach * n, reach * n]), (len(theta), 1, 1))
    arm = np.stack([np.zeros_like(G), G], axis=1)
    return Pose([_carry(R, G, o) for o in outline], G, size, [axle, arm])


def _rot_y(a: np.ndarray) -> np.ndarray:
    c, s, o, z = np.cos(a), np.sin(a), np.ones_like(a), np.zeros_like(a)
    rows = (np.stack([c, z, s], -1), np.stack([z, o, z], -1), np.stack([-s, z, c], -1))
    return np.stack(rows, -2)


def _cone(result: Result, name: str, component) -> Pose:
    """ConeOnIncline, in the incline's axes (x down the slope, z its normal, the plane
    z = 0): Q = Rz(phi) Ry(-beta) Rx(-phi / sin(beta)), the apex at the origin; the base
    rim, slant lines from the apex to it and G's path."""
    p = component.values
    sin_b = p["R"] / p["h"]
    H = p["h"] * math.sqrt(1 - sin_b**2)
    phi = result[f"{name}.phi"]
    Q = _rot_z(phi) @ _rot_y(np.full_like(phi, -math.asin(sin_b))) @ _rot_x(-phi / sin_b)
    origin = np.zeros((len(phi), 3))
    rim = circle(p["R"], 0) + np.array([H, 0.0, 0.0])
    slants = [np.array([[0.0, 0.0, 0.0], rim[k]]) for k in range(0, CIRCLE, CIRCLE // 4)]
    G = _carry(Q, origin, np.array([[3 * H / 4, 0.0, 0.0]]))[:, 0]
    return Pose([_carry(Q, origin, o) for o in (rim, *slants)], G, p["h"])


# component class name -> (the outputs its drawer reads, the drawer)
DRAWERS = {
    "WobblingDisk": (("phi", "theta", "psi", "phi_dot", "theta_dot", "psi_dot"), _disk),
    "RollingCoin": (("x", "y", "phi", "theta", "psi", "x_C", "y_C"), _coin),
    "TorqueFreeBody": (("q0", "q1", "q2", "q3"), _quaternion_body),
    "NutationDamperBody": (("q0", "q1", "q2", "q3"), _quaternion_body),
    "RigidBodyOnString": (("x", "y", "z", "B_X", "B_Y", "B_Z",
                           *(f"{b}_{a}" for b in "xyz" for a in "XYZ")), _string_body),
    "RigidBodyOnAxle": (("theta",), _axle_body),
    "ConeOnIncline": (("phi",), _cone),
}


def bodies(assembly) -> dict[str, tuple]:
    """The instances of `assembly` that can be drawn: name -> (component, needs, drawer)."""
    return {name: (comp, *DRAWERS[type(comp).__name__])
            for name, comp in assembly.components.items() if type(comp).__name__ in DRAWERS}


def animation_record(scene) -> list[str] | None:
    """The scene's record with what its bodies' drawers read added (None: everything is
    recorded already). Raises AssemblyError, naming the drawable bodies, when it has none."""
    found = bodies(scene.build())
    if not found:
        raise AssemblyError(
            f"scene '{scene.name}' has no body to animate; --animate draws "
            f"{', '.join(sorted(DRAWERS))} (scenes: wobbling_disk, thrown_disk, "
            "wobble_exercise, nutation_damper, string_body, axle_pendulum, axle_inertia, "
            "cone_incline, coin_rolling and the other coin scenes)")
    if scene.record is None:
        return None
    extra = [f"{name}.{k}" for name, (_, needs, _) in found.items() for k in needs]
    return list(dict.fromkeys([*scene.record, *extra]))


def ffmpeg_executable() -> str | None:
    """The ffmpeg that writes .mp4: the one on the PATH, else the binary the optional
    imageio-ffmpeg wheel ships (``pip install mechfmu[animate]``), else None."""
    found = shutil.which("ffmpeg")
    if found:
        return found
    try:
        import imageio_ffmpeg
    except ImportError:
        return None
    try:
        return imageio_ffmpeg.get_ffmpeg_exe()
    except RuntimeError:  # the wheel's binary missing (a platform it does not cover)
        return None


def check_animation_file(path: str | Path) -> Path:
    """The --animate file, checked before the run: .gif (Pillow) or .mp4 (needs ffmpeg)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise AssemblyError(f"--animate {path}: the file must end in .gif or .mp4, not "
                            f"'{path.suffix or '(no suffix)'}'")
    if suffix == ".mp4" and ffmpeg_executable() is None:
        raise AssemblyError(f"--animate {path}: writing .mp4 needs ffmpeg, and there is none "
                            "on the PATH nor from imageio-ffmpeg; pip install "
                            "'mechfmu[animate]' (or install ffmpeg) or write a .gif")
    if not path.parent.is_dir():
        raise AssemblyError(f"--animate {path}: folder {path.parent} does not exist")
    return path


def frame_indices(n: int, frames: int = FRAMES) -> np.ndarray:
    """Output indices drawn: evenly spread over the run, first and last included."""
    return np.unique(np.linspace(0, n - 1, max(2, min(frames, n))).round().astype(int))


def animate(result: Result, assembly, path: str | Path, title: str = "",
            frames: int = FRAMES, fps: int = FPS) -> list[str]:
    """Render the run's bodies in 3-D to `path` (.gif or .mp4), one frame per sampled
    output: each body's outline, the path its traced point has followed so far, its
    lines, and the time. Returns the time labels drawn, frame by frame."""
    path = check_animation_file(path)
    plt = pyplot()
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter
    poses = [drawer(result, name, comp) for name, (comp, _, drawer) in bodies(assembly).items()]
    if not poses:
        raise AssemblyError(f"{assembly.name}: no body to animate")
    t = result["time"]
    chosen = frame_indices(len(t), frames)
    everything = np.concatenate(
        [np.concatenate([o[chosen].reshape(-1, 3) for o in pose.outlines]
                        + [pose.path[chosen]] + [line[chosen].reshape(-1, 3)
                                                  for line in pose.lines]) for pose in poses])
    middle = (everything.max(axis=0) + everything.min(axis=0)) / 2
    half = float((everything.max(axis=0) - everything.min(axis=0)).max()) / 2 or 1.0
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    for k, (low, high) in enumerate(zip(middle - half, middle + half)):
        (ax.set_xlim, ax.set_ylim, ax.set_zlim)[k](low, high)
    ax.set_box_aspect((1, 1, 1))  # equal scales: the body drawn to scale
    ax.set_xlabel("X [m]")
    ax.set_ylabel("Y [m]")
    ax.set_zlabel("Z [m]")
    ax.set_title(textwrap.fill(title, 60), fontsize=9)
    drawn = []
    for k, pose in enumerate(poses):
        colour = plt.cm.tab10(k)
        drawn.append(([ax.plot([], [], [], color=colour, lw=1.8)[0] for _ in pose.outlines],
                      ax.plot([], [], [], color=colour, lw=0.8, alpha=0.6)[0],
                      [ax.plot([], [], [], color="0.3", lw=1.0)[0] for _ in pose.lines]))
    label = ax.text2D(0.03, 0.95, "", transform=ax.transAxes)
    labels = []

    def update(frame: int):
        i = chosen[frame]
        for pose, (outlines, trace, lines) in zip(poses, drawn):
            for artist, outline in zip(outlines, pose.outlines):
                artist.set_data_3d(*outline[i].T)
            trace.set_data_3d(*pose.path[:i + 1].T)
            for artist, line in zip(lines, pose.lines):
                artist.set_data_3d(*line[i].T)
        text = f"t = {t[i]:.2f} s"
        label.set_text(text)
        if len(labels) == frame:  # a writer may draw the first frame twice
            labels.append(text)
        return []

    animation = FuncAnimation(fig, update, frames=len(chosen), blit=False)
    import matplotlib
    gif = path.suffix.lower() == ".gif"
    # matplotlib looks for "ffmpeg" on the PATH unless told where it is
    settings = {} if gif else {"animation.ffmpeg_path": ffmpeg_executable()}
    with matplotlib.rc_context(settings):
        animation.save(str(path), writer=PillowWriter(fps=fps) if gif else FFMpegWriter(fps=fps),
                       dpi=80)
    plt.close(fig)
    return labels


__all__ = ["DRAWERS", "Pose", "animate", "animation_record", "bodies", "box_dimensions",
           "box_edges", "check_animation_file", "circle", "ffmpeg_executable", "frame_indices",
           "quaternion_matrices"]
