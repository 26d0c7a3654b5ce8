#!/usr/bin/env python3
"""Chapter 12's diagrams (book/images/12_*.svg, and 12_furnace.png): microfacets with masking
and shadowing; Fresnel reflectance against angle (glass, gold and copper, exact and Schlick);
Snell's law and total internal reflection; the two visible-normal samplers (Heitz's projected
hemisphere, Dupuy and Benyoub's spherical cap); the energy a white rough metal and rough glass
lose to single scattering, by Monte Carlo; and, given a folder of furnace renders (.pfm), their
radiance in false colour.

  tools/diagrams/ch12.py [OUT_DIR] [FURNACE_DIR]     (default: book/images, no furnace)
"""
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("svg")
import matplotlib.colors  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Arc, Circle, FancyArrowPatch  # noqa: E402

BLUE, GREY, RED, GOLD, GREEN = "#2a7ab0", "#555555", "#c0392b", "#d4a017", "#2e8b57"

# The complex indices of material_scenes.cpp (Johnson and Christy's data at about 650, 550 and
# 450 nm: red, green, blue).
GOLD_ETA, GOLD_K = (0.143, 0.374, 1.442), (3.983, 2.385, 1.603)
COPPER_ETA, COPPER_K = (0.200, 0.924, 1.102), (3.912, 2.452, 2.142)


def arrow(ax, start, end, colour, width=1.3, style="-|>", dashed=False):
    ax.add_patch(FancyArrowPatch(start, end, arrowstyle=style, mutation_scale=11, color=colour,
                                 linewidth=width, linestyle="--" if dashed else "-"))


def save(fig, path):
    fig.savefig(path, format="svg", metadata={"Date": None}, bbox_inches="tight")
    plt.close(fig)


def blank(ax, xlim, ylim):
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal")
    ax.axis("off")


# ------------------------------------------------------------------------------------------
# Microfacets, masking and shadowing.

def profile():
    """A rough surface's profile: a zigzag of facets (x, height), the same on every run."""
    xs = np.linspace(-3.0, 3.0, 17)
    heights = [0.0, 0.35, 0.05, 0.5, 0.1, 0.25, -0.05, 0.45, 0.0, 0.3, 0.05, 0.55, 0.1, 0.2,
               -0.05, 0.4, 0.0]
    return list(zip(xs, heights))


def blocked(points, start, direction):
    """Whether the ray from start along direction meets the profile (other than at start)."""
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        ex, ey = x1 - x0, y1 - y0
        det = direction[0] * (-ey) - direction[1] * (-ex)
        if abs(det) < 1e-12:
            continue
        rx, ry = x0 - start[0], y0 - start[1]
        t = (rx * (-ey) - ry * (-ex)) / det
        s = (direction[0] * ry - direction[1] * rx) / det
        if t > 1e-6 and 0.0 <= s <= 1.0:
            return True
    return False


def microfacets(out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    points = profile()
    facets = list(zip(points, points[1:]))

    def normal_of(facet):
        (x0, y0), (x1, y1) = facet
        n = np.array([-(y1 - y0), x1 - x0])
        return n / np.linalg.norm(n)

    def middle(facet):
        (x0, y0), (x1, y1) = facet
        return np.array([(x0 + x1) / 2, (y0 + y1) / 2])

    # Left: of all the facets, the one whose normal is the half vector sends the light to the
    # eye (wi and wo both point away from the surface).
    ax = axes[0]
    blank(ax, (-3.2, 3.2), (-0.5, 3.0))
    ax.plot(*zip(*points), color=GREY, linewidth=1.8)
    ax.plot([-3, 3], [0.2, 0.2], color=GREY, linewidth=0.8, linestyle=":")
    arrow(ax, (-2.8, 0.2), (-2.8, 1.2), GREY)
    ax.text(-2.7, 1.1, "n (the surface)", fontsize=8.5, color=GREY)
    wi = np.array([-math.sin(math.radians(55)), math.cos(math.radians(55))])
    wo = np.array([math.sin(math.radians(15)), math.cos(math.radians(15))])
    h = (wi + wo) / np.linalg.norm(wi + wo)
    facet = max(facets[4:12], key=lambda f: float(np.dot(normal_of(f), h)))
    mid, m = middle(facet), normal_of(facet)
    ax.plot(*zip(*facet), color=RED, linewidth=3.5, solid_capstyle="butt")
    arrow(ax, tuple(mid + 2.3 * wi), tuple(mid + 0.05 * wi), GOLD)
    ax.text(*(mid + 2.35 * wi + np.array([-0.3, 0.05])), "from the light (wi)", fontsize=8.5,
            color=GOLD)
    arrow(ax, tuple(mid + 0.05 * wo), tuple(mid + 2.3 * wo), BLUE)
    ax.text(*(mid + 2.35 * wo + np.array([-0.2, 0.05])), "to the eye (wo)", fontsize=8.5,
            color=BLUE)
    arrow(ax, tuple(mid), tuple(mid + 0.9 * m), RED)
    ax.text(*(mid + 0.95 * m + np.array([0.08, -0.1])), "m = h", fontsize=9, color=RED)
    ax.set_title("A rough surface: tiny mirrors. The one that sends wi to wo has the\n"
                 "half vector h = (wi + wo) / |wi + wo| for its normal; D(h) says how many do",
                 fontsize=8.5)
    # Right: light at a low angle; facets it cannot reach are shadowed, facets the eye cannot
    # see are masked. G2 is the share of facets neither hides.
    ax = axes[1]
    blank(ax, (-3.2, 3.2), (-0.9, 3.0))
    light = np.array([-math.cos(math.radians(18)), math.sin(math.radians(18))])  # towards it
    eye = np.array([math.cos(math.radians(47)), math.sin(math.radians(47))])
    for facet in facets:
        mid, normal = middle(facet), normal_of(facet)
        lit = np.dot(normal, light) > 0 and not blocked(points, mid, light)
        seen = np.dot(normal, eye) > 0 and not blocked(points, mid, eye)
        colour = GOLD if lit and seen else (BLUE if lit else (RED if seen else GREY))
        ax.plot(*zip(*facet), color=colour, linewidth=3.2, solid_capstyle="butt")
    for start in np.linspace(-2.0, 2.0, 5):
        p = np.array([start, 0.3])
        arrow(ax, tuple(p + 2.6 * light + np.array([0, 0.4])),
              tuple(p + 1.7 * light + np.array([0, 0.4])), GOLD, 0.9)
    ax.text(-3.1, 1.85, "light, low", fontsize=8.5, color=GOLD)
    arrow(ax, (1.5, 1.3), tuple(np.array([1.5, 1.3]) + 1.0 * eye), BLUE, 1.2)
    ax.text(1.75, 1.3, "to the eye", fontsize=8.5, color=BLUE)
    for i, (colour, label) in enumerate([(GOLD, "lit and seen"), (RED, "seen, in shadow"),
                                         (BLUE, "lit, hidden from the eye (masked)"),
                                         (GREY, "neither")]):
        ax.text(-3.0 + 3.6 * (i % 2), -0.45 - 0.35 * (i // 2), "■ " + label, color=colour,
                fontsize=8)
    ax.set_title("Masking and shadowing: Smith's G1(w) is the share of the facets facing w\n"
                 "that w reaches; G2(wo, wi) the share that both reach", fontsize=8.5)
    save(fig, out / "12_microfacets.svg")


# ------------------------------------------------------------------------------------------
# Fresnel.

def fresnel_dielectric(cos_i, eta):
    """microfacet.h's fresnel_dielectric, in double."""
    if cos_i < 0:
        eta, cos_i = 1 / eta, -cos_i
    sin2_t = (1 - cos_i * cos_i) / (eta * eta)
    if sin2_t >= 1:
        return 1.0
    cos_t = math.sqrt(1 - sin2_t)
    parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    return 0.5 * (parallel ** 2 + perpendicular ** 2)


def fresnel_conductor(cos_i, eta, k):
    """microfacet.h's fresnel_conductor: the dielectric formula with a complex index."""
    n = complex(eta, k)
    cos_t = np.sqrt(1 - (1 - cos_i * cos_i) / (n * n))
    parallel = (n * cos_i - cos_t) / (n * cos_i + cos_t)
    perpendicular = (cos_i - n * cos_t) / (cos_i + n * cos_t)
    return 0.5 * (abs(parallel) ** 2 + abs(perpendicular) ** 2)


def schlick(f0, cos_i):
    return f0 + (1 - f0) * (1 - cos_i) ** 5


def fresnel(out):
    angles = np.linspace(0, 90, 361)
    cosines = np.cos(np.radians(angles))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    ax = axes[0]
    ax.plot(angles, [fresnel_dielectric(c, 1.5) for c in cosines], color=BLUE,
            label="glass (1.5), from air: exact")
    ax.plot(angles, [schlick(0.04, c) for c in cosines], color=BLUE, linestyle="--",
            label="Schlick, F0 = 0.04")
    ax.plot(angles, [fresnel_dielectric(-c, 1.5) for c in cosines], color=RED,
            label="from inside the glass: exact")
    critical = math.degrees(math.asin(1 / 1.5))
    ax.axvline(critical, color=RED, linewidth=0.8, linestyle=":")
    ax.text(critical + 1, 0.55, f"critical angle {critical:.1f}°:\ntotal internal "
            "reflection beyond", fontsize=8, color=RED)
    ax.set_xlabel("angle of incidence (degrees)")
    ax.set_ylabel("reflectance F")
    ax.set_title("A dielectric: 4% head-on, all of it at grazing", fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_xlim(0, 90)
    ax.set_ylim(0, 1.02)
    ax = axes[1]
    channels = (("red", RED), ("green", GREEN), ("blue", BLUE))
    for name, eta, k, style in (("gold", GOLD_ETA, GOLD_K, "-"),
                                ("copper", COPPER_ETA, COPPER_K, "-.")):
        for (channel, colour), e, kk in zip(channels, eta, k):
            exact = [fresnel_conductor(c, e, kk) for c in cosines]
            ax.plot(angles, exact, color=colour, linestyle=style, linewidth=1.2,
                    label=f"{name}, {channel}" if name == "gold" or channel == "red" else None)
            if name == "gold":
                ax.plot(angles, [schlick(exact[0], c) for c in cosines], color=colour,
                        linestyle=":", linewidth=1.0)
    ax.plot([], [], color=GREY, linestyle="-", label="gold: exact (eta + i k)")
    ax.plot([], [], color=GREY, linestyle=":", label="gold: Schlick from the same F0")
    ax.plot([], [], color=GREY, linestyle="-.", label="copper: exact")
    ax.set_xlabel("angle of incidence (degrees)")
    ax.set_title("Conductors: coloured head-on, white at grazing; Schlick misses the dip",
                 fontsize=10)
    ax.legend(fontsize=7.5, loc="lower left", ncol=2)
    ax.set_xlim(0, 90)
    ax.set_ylim(0, 1.02)
    save(fig, out / "12_fresnel.svg")


# ------------------------------------------------------------------------------------------
# Snell's law and total internal reflection.

def snell(out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    eta = 1.5
    critical = math.degrees(math.asin(1 / eta))
    for ax, inside in zip(axes, (False, True)):
        blank(ax, (-2.3, 2.3), (-2.2, 2.2))
        ax.fill_between([-2.2, 2.2], [-2.1, -2.1], [0, 0], color="#e3f0f7")
        ax.plot([-2.2, 2.2], [0, 0], color=GREY, linewidth=1.5)
        ax.plot([0, 0], [-2.0, 2.0], color=GREY, linewidth=0.7, linestyle=":")
        ax.text(2.15, 0.08, "air, n = 1", ha="right", fontsize=8.5, color=GREY)
        ax.text(2.15, -0.25, "glass, n = 1.5", ha="right", fontsize=8.5, color=BLUE)
        angles = (15, 35, critical, 60) if inside else (0, 30, 60, 85)
        colours = (BLUE, GREEN, GOLD, RED)
        side = -1 if inside else 1  # where the light comes from
        n1, n2 = (eta, 1.0) if inside else (1.0, eta)
        for i, (angle, colour) in enumerate(zip(angles, colours)):
            a = math.radians(angle)
            start = (-1.9 * math.sin(a), side * 1.9 * math.cos(a))
            arrow(ax, start, (0, 0), colour, 1.1)
            s = min(1.0, n1 / n2 * math.sin(a))
            refracts = inside is False or angle <= critical
            if refracts:
                t = math.asin(s)
                arrow(ax, (0, 0), (1.9 * math.sin(t), -side * 1.9 * math.cos(t)), colour, 1.1)
                label = f"{angle:.0f}° → {math.degrees(t):.1f}°"
                if inside and i == 2:
                    label = f"{angle:.1f}° → 90°: the critical angle"
            else:
                label = f"{angle:.0f}°: totally reflected"
            # the reflection, faint where light also refracts, whole past the critical angle
            arrow(ax, (0, 0), (1.6 * math.sin(a), side * 1.6 * math.cos(a)), colour,
                  0.5 if refracts else 1.1, dashed=refracts)
            ax.text(-2.25, side * (2.05 - 0.27 * i) - (0.1 if inside else 0), label,
                    fontsize=8, color=colour)
        if inside:
            ax.set_title(f"From inside: past asin(1 / 1.5) = {critical:.1f}° no refracted "
                         "ray exists,\nand everything is reflected (total internal reflection)",
                         fontsize=9)
        else:
            ax.set_title("From air: n1 sin θ1 = n2 sin θ2; the whole hemisphere is squeezed\n"
                         f"into a cone of {critical:.1f}°: radiance inside is n² = 2.25 times "
                         "larger", fontsize=9)
    save(fig, out / "12_snell_tir.svg")


# ------------------------------------------------------------------------------------------
# Visible-normal sampling.

def vndf(out):
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4))
    view_angle = math.radians(50)
    v = np.array([math.sin(view_angle), math.cos(view_angle)])
    t1 = np.array([v[1], -v[0]])  # perpendicular to v, in the plane of the drawing
    # (a) Heitz 2018: in the stretched configuration the surface is a unit hemisphere; the
    # normals wo sees, weighted by the area they show it, are its projection onto the disc
    # perpendicular to wo. A uniform point on the disc, lifted along wo, is a visible normal.
    ax = axes[0]
    blank(ax, (-1.6, 2.2), (-1.3, 2.2))
    ax.add_patch(Arc((0, 0), 2, 2, theta1=0, theta2=180, color=GREY, linewidth=1.5))
    ax.plot([-1.3, 1.3], [0, 0], color=GREY, linewidth=1.0)
    arrow(ax, (0, 0), tuple(1.9 * v), BLUE)
    ax.text(*(1.95 * v), "wo (stretched)", fontsize=8.5, color=BLUE)
    rim = math.cos(view_angle)  # where the hemisphere's rim at +x projects on t1
    ax.plot(*zip(-1 * t1, 1 * t1), color=GREY, linewidth=0.8, linestyle=":")
    ax.plot(*zip(-1 * t1, rim * t1), color=RED, linewidth=3, solid_capstyle="butt")
    ax.text(*(-1.0 * t1 + np.array([-0.45, 0.1])), "the disc ⊥ wo", fontsize=8, color=RED)
    for s in (-0.7, -0.15, 0.4):
        p = s * t1
        height = math.sqrt(max(0.0, 1 - s * s))  # along v, to the sphere
        m = p + height * v
        ax.plot(*zip(p, m), color=GOLD, linewidth=0.9, linestyle="--")
        ax.plot(*p, "o", color=GOLD, markersize=4)
        arrow(ax, (0, 0), tuple(m), GOLD, 0.9)
    ax.text(-1.55, -1.25, "a uniform point on the disc, lifted along wo onto the hemisphere,\n"
            "is a normal drawn by the area it shows wo; the part of the disc the\n"
            "hemisphere's base hides (dotted) is squashed onto the visible part (red)",
            fontsize=7.8, color=GREY)
    ax.set_title("Heitz 2018: the visible hemisphere projected onto a disc", fontsize=10)
    # (b) Dupuy and Benyoub 2023: the mirror directions of the visible normals are uniform on
    # the spherical cap z > -wo.z; the normal is the half vector of wo and such a direction.
    ax = axes[1]
    blank(ax, (-1.6, 2.2), (-1.5, 2.2))
    ax.add_patch(Circle((0, 0), 1, fill=False, color=GREY, linewidth=0.8, linestyle=":"))
    cap_z = -v[1]
    cap_angle = math.degrees(math.asin(cap_z))
    ax.add_patch(Arc((0, 0), 2, 2, theta1=cap_angle, theta2=180 - cap_angle, color=RED,
                     linewidth=3))
    ax.plot([-1.3, 1.3], [cap_z, cap_z], color=RED, linewidth=0.8, linestyle="--")
    ax.text(1.05, cap_z - 0.2, "z = -wo.z", fontsize=8, color=RED)
    ax.plot([-1.3, 1.3], [0, 0], color=GREY, linewidth=1.0)
    arrow(ax, (0, 0), tuple(1.0 * v), BLUE)
    ax.text(*(1.05 * v), "wo", fontsize=9, color=BLUE)
    d = np.array([-math.sqrt(1 - 0.3 ** 2), -0.3])
    arrow(ax, (0, 0), tuple(d), GOLD, 1.1)
    ax.text(*(d + np.array([-0.15, -0.2])), "d, uniform on the cap", fontsize=8, color=GOLD)
    m = (v + d) / np.linalg.norm(v + d)
    ax.plot(*zip(v, v + d), color=GREY, linewidth=0.7, linestyle="--")
    ax.plot(*zip(d, v + d), color=GREY, linewidth=0.7, linestyle="--")
    arrow(ax, (0, 0), tuple(1.3 * m), GREEN, 1.4)
    ax.text(*(1.35 * m + np.array([0.03, 0])), "m = (wo + d) / |wo + d|", fontsize=8.5,
            color=GREEN)
    ax.text(-1.55, -1.45, "one uniform direction on a cap, one sum, one normalisation:\n"
            "no frame to build, no branch; then the stretch is undone", fontsize=7.8,
            color=GREY)
    ax.set_title("Dupuy and Benyoub 2023: a spherical cap", fontsize=10)
    save(fig, out / "12_vndf.svg")


# ------------------------------------------------------------------------------------------
# The energy one bounce loses, by Monte Carlo over the visible normals (Heitz 2018's sampler
# in numpy): for F = 1, E(mu) is the mean of G2 / G1(wo) over the reflected directions.

def lambda_ggx(z, sin2, alpha):
    return 0.5 * (np.sqrt(z * z + alpha * alpha * sin2) / np.abs(z) - 1.0)


def single_scattering(mu, alpha, rng, samples=40000):
    wo = np.array([math.sqrt(max(0.0, 1 - mu * mu)), 0.0, mu])
    view = np.array([alpha * wo[0], alpha * wo[1], wo[2]])
    view /= np.linalg.norm(view)
    length2 = view[0] ** 2 + view[1] ** 2
    t1 = np.array([-view[1], view[0], 0]) / math.sqrt(length2) if length2 > 0 else \
        np.array([1.0, 0, 0])
    t2 = np.cross(view, t1)
    u, w = rng.random(samples), rng.random(samples)
    r, phi = np.sqrt(u), 2 * np.pi * w
    p1 = r * np.cos(phi)
    s = 0.5 * (1 + view[2])
    p2 = (1 - s) * np.sqrt(np.maximum(0, 1 - p1 * p1)) + s * r * np.sin(phi)
    p3 = np.sqrt(np.maximum(0, 1 - p1 * p1 - p2 * p2))
    n = np.outer(p1, t1) + np.outer(p2, t2) + np.outer(p3, view)
    m = np.stack([alpha * n[:, 0], alpha * n[:, 1], np.maximum(n[:, 2], 1e-7)], axis=1)
    m /= np.linalg.norm(m, axis=1)[:, None]
    wi = 2 * (m @ wo)[:, None] * m - wo
    ok = wi[:, 2] > 0
    lambda_o = lambda_ggx(wo[2], wo[0] ** 2 + wo[1] ** 2, alpha)
    lambda_i = lambda_ggx(np.where(ok, wi[:, 2], 1.0), wi[:, 0] ** 2 + wi[:, 1] ** 2, alpha)
    weight = np.where(ok, (1 + lambda_o) / (1 + lambda_o + lambda_i), 0.0)
    return float(weight.mean())


def energy_loss(out):
    rng = np.random.default_rng(12)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    mus = np.linspace(0.02, 1.0, 25)
    ax = axes[0]
    for roughness, colour in ((0.25, BLUE), (0.5, GREEN), (0.75, GOLD), (1.0, RED)):
        alpha = roughness * roughness
        ax.plot(mus, [single_scattering(mu, alpha, rng) for mu in mus], color=colour,
                label=f"roughness {roughness} (alpha {alpha:.3g})")
    ax.axhline(1 - math.log(2), color=RED, linewidth=0.6, linestyle=":")
    ax.text(0.52, 1 - math.log(2) - 0.07, "1 − ln 2 = 0.307: alpha 1, head-on",
            fontsize=8, color=RED)
    ax.set_xlabel("cos θo")
    ax.set_ylabel("E(cos θo): the share one bounce returns")
    ax.set_title("A white rough metal (F = 1), one bounce", fontsize=10)
    ax.set_ylim(0, 1.02)
    ax.legend(fontsize=8, loc="lower left")
    ax = axes[1]
    roughnesses = np.linspace(0.0, 1.0, 21)
    nodes = np.linspace(0.0, 1.0, 21) ** 2  # E_avg = 2 ∫ E mu dmu, trapezoids in mu
    lost = []
    for roughness in roughnesses:
        alpha = max(roughness * roughness, 1e-4)
        e = np.array([single_scattering(max(mu, 1e-3), alpha, rng, 20000) for mu in nodes])
        average = float(np.sum((e[1:] * nodes[1:] + e[:-1] * nodes[:-1]) * np.diff(nodes)))
        lost.append(1 - average)
    ax.plot(roughnesses, lost, color=RED, marker="o", markersize=3)
    ax.set_xlabel("roughness (alpha = roughness²)")
    ax.set_ylabel("1 − E_avg: the share lost")
    ax.set_title("What compensation gives back (Kulla and Conty)", fontsize=10)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, max(lost) * 1.1)
    save(fig, out / "12_energy_loss.svg")


def dielectric_scattering(mu, alpha, eta, rng, samples=20000):
    """E(mu, alpha, eta) of a rough dielectric, reflection and refraction together, radiance
    factor left out: Dupuy and Benyoub's visible normals, each weighted by what it returns,
    F G2(wo, wr) / G1(wo) + (1 - F) G2(wo, wt) / G1(wo). eta: the far side's index over wo's."""
    wo = np.array([math.sqrt(max(0.0, 1 - mu * mu)), 0.0, mu])
    view = np.array([alpha * wo[0], 0.0, wo[2]])
    view /= np.linalg.norm(view)
    u, v = rng.random(samples), rng.random(samples)
    z = (1 - v) * (1 + view[2]) - view[2]
    sin_theta = np.sqrt(np.maximum(0, 1 - z * z))
    n = np.stack([sin_theta * np.cos(2 * np.pi * u) + view[0],
                  sin_theta * np.sin(2 * np.pi * u), z + view[2]], axis=1)
    m = np.stack([alpha * n[:, 0], alpha * n[:, 1], np.maximum(n[:, 2], 0)], axis=1)
    m /= np.maximum(np.linalg.norm(m, axis=1), 1e-30)[:, None]
    c = np.clip(m @ wo, 0, 1)
    sin2_t = (1 - c * c) / (eta * eta)
    cos_t = np.sqrt(np.maximum(0, 1 - sin2_t))
    parallel = (eta * c - cos_t) / (eta * c + cos_t)
    perpendicular = (c - eta * cos_t) / (c + eta * cos_t)
    fresnel = np.where(sin2_t >= 1, 1.0, 0.5 * (parallel ** 2 + perpendicular ** 2))
    lambda_o = lambda_ggx(wo[2], wo[0] ** 2, alpha)

    def kept(w, side):  # G2(wo, w) / G1(wo), where w lies on its side of the surface
        ok = w[:, 2] * side > 0
        lambda_w = lambda_ggx(np.where(ok, w[:, 2], 1.0), w[:, 0] ** 2 + w[:, 1] ** 2, alpha)
        return np.where(ok, (1 + lambda_o) / (1 + lambda_o + lambda_w), 0.0)

    reflected = 2 * c[:, None] * m - wo
    refracted = -wo / eta + m * (c / eta - cos_t)[:, None]
    weight = fresnel * kept(reflected, 1) + (1 - fresnel) * kept(refracted, -1)
    return float(np.where(c > 0, weight, 0.0).mean())


def glass_energy_loss(out):
    rng = np.random.default_rng(13)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    roughnesses = np.linspace(0.0, 1.0, 11)
    nodes = np.linspace(0.0, 1.0, 17) ** 2  # E_avg = 2 ∫ E mu dmu, trapezoids in mu
    for eta, colour in ((1.5, BLUE), (2.4, RED)):
        for side, style in (("outside", "-"), ("inside", "--")):
            lost = []
            for roughness in roughnesses:
                alpha = max(roughness * roughness, 1e-4)
                ratio = eta if side == "outside" else 1 / eta
                e = np.array([dielectric_scattering(max(mu, 1e-3), alpha, ratio, rng)
                              for mu in nodes])
                average = float(np.sum((e[1:] * nodes[1:] + e[:-1] * nodes[:-1]) *
                                       np.diff(nodes)))
                lost.append(1 - average)
            ax.plot(roughnesses, lost, color=colour, linestyle=style, marker="o", markersize=3,
                    label=f"η = {eta}, light from {side}")
            print(f"glass eta {eta} from {side}: 1 - E_avg by roughness "
                  + ", ".join(f"{r:.1f}: {x:.3f}" for r, x in zip(roughnesses, lost)))
    ax.set_xlabel("roughness (alpha = roughness²)")
    ax.set_ylabel("1 − E_avg: the share one scattering loses")
    ax.set_title("Rough glass, reflection and refraction together", fontsize=10)
    ax.set_xlim(0, 1)
    ax.set_ylim(0, None)
    ax.legend(fontsize=8, loc="upper left")
    save(fig, out / "12_glass_energy_loss.svg")


# ------------------------------------------------------------------------------------------
# The furnace renders in false colour.

def read_pfm(path):
    with open(path, "rb") as f:
        assert f.readline().strip() == b"PF"
        width, height = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(height, width, 3)[::-1]  # the file holds the bottom row first


FURNACES = (("glass", "smooth glass"),
            ("rough_glass", "rough glass, roughness 0.6,\ncompensated"),
            ("metal", "white metal, roughness 1,\ncompensated"),
            ("metal_plain", "white metal, roughness 1,\nno compensation"),
            ("inside", "the camera inside\nthe smooth glass"))


def sphere_masks(image):
    """The furnace sphere's disc (radius 1 at distance 4 seen through a 30° field of view) and
    its centre, as masks over the image."""
    h, w = image.shape
    y, x = np.mgrid[0:h, 0:w]
    radius = math.tan(math.asin(0.25)) / math.tan(math.radians(15)) * h / 2
    distance2 = (x + 0.5 - w / 2) ** 2 + (y + 0.5 - h / 2) ** 2
    return distance2 < (radius * 0.97) ** 2, distance2 < (radius * 0.1) ** 2


def furnace(out, folder):
    fig, axes = plt.subplots(1, len(FURNACES), figsize=(14, 3.6))
    norm = matplotlib.colors.TwoSlopeNorm(vmin=0.0, vcenter=1.0, vmax=2.5)
    for ax, (name, title) in zip(axes, FURNACES):
        image = read_pfm(folder / f"12_furnace_{name}.pfm").mean(axis=2)
        disc, centre = sphere_masks(image)
        if name == "inside":  # every pixel sees the sky through the glass
            disc = np.ones_like(disc)
        shown = ax.imshow(image, cmap="RdBu", norm=norm)
        ax.axis("off")
        ax.set_title(f"{title}\nmean {image[disc].mean():.3f}, centre "
                     f"{image[centre].mean():.3f}", fontsize=9)
        print(f"{name}: mean over the sphere {image[disc].mean():.4f}, at its centre "
              f"{image[centre].mean():.4f}")
    bar = fig.colorbar(shown, ax=axes, fraction=0.02, pad=0.02)
    bar.set_label("radiance (the sky is 1)")
    fig.savefig(out / "12_furnace.png", dpi=100, bbox_inches="tight",
                metadata={"Software": None})
    plt.close(fig)


GLASS_ROUGHNESSES = ("0", "0.25", "0.5", "0.75", "1")


def furnace_glass(out, folder):
    """Rough glass spheres (index 1.5) in the furnace, one scattering only above, with Turquin's
    scale below."""
    fig, axes = plt.subplots(2, len(GLASS_ROUGHNESSES), figsize=(12, 5.6))
    norm = matplotlib.colors.TwoSlopeNorm(vmin=0.0, vcenter=1.0, vmax=2.0)
    for row, (kind, label) in enumerate((("plain", "no compensation"),
                                         ("compensated", "compensated"))):
        for ax, roughness in zip(axes[row], GLASS_ROUGHNESSES):
            image = read_pfm(folder / f"12_furnace_glass_{roughness}_{kind}.pfm").mean(axis=2)
            disc, centre = sphere_masks(image)
            shown = ax.imshow(image, cmap="RdBu", norm=norm)
            ax.axis("off")
            ax.set_title(f"roughness {roughness}\nmean {image[disc].mean():.3f}, "
                         f"centre {image[centre].mean():.3f}", fontsize=8)
            if roughness == GLASS_ROUGHNESSES[0]:
                ax.text(-0.08, 0.5, label, transform=ax.transAxes, rotation=90,
                        ha="right", va="center", fontsize=9)
            print(f"glass {roughness} {kind}: mean over the sphere {image[disc].mean():.4f}, "
                  f"at its centre {image[centre].mean():.4f}")
    bar = fig.colorbar(shown, ax=axes, fraction=0.02, pad=0.02)
    bar.set_label("radiance (the sky is 1)")
    fig.savefig(out / "12_furnace_glass.png", dpi=100, bbox_inches="tight",
                metadata={"Software": None})
    plt.close(fig)


def main():
    plt.rcParams.update({"svg.hashsalt": "rt-course-ch12", "font.family": "DejaVu Sans"})
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("book/images")
    out.mkdir(parents=True, exist_ok=True)
    microfacets(out)
    fresnel(out)
    snell(out)
    vndf(out)
    energy_loss(out)
    glass_energy_loss(out)
    if len(sys.argv) > 2:
        furnace(out, Path(sys.argv[2]))
        furnace_glass(out, Path(sys.argv[2]))


if __name__ == "__main__":
    main()
