"""Mitsuba 3's side of `refract bench prism --peer mitsuba` (refract runs
this file with the Python of the environment scripts/mitsuba-venv makes).

    python mitsuba_prism.py SCENE.json OUT_DIR SPP[,SPP...]

SCENE.json is the bench's scene as refract built it (the prism's faces,
the screen, the camera, the beam, the light's spectrum, the glass's
two-term Cauchy fit and the wavelength bands). Mitsuba 3 has no
dispersive dielectric, so each band is rendered on its own: the beam's
spectrum restricted to the band, the prism a `dielectric` of the Cauchy
index at the band's centre; the bands' images add up to the whole. The
integrator is the particle tracer (`ptracer`): light paths from the beam,
through the glass, onto the matte screen, connected to the camera. The
variant is `llvm_ad_spectral` where an LLVM of version 16 or newer is
installed (Debian: `apt-get install libllvm19`; or DRJIT_LIBLLVM_PATH),
else `scalar_spectral`. At SPP samples per pixel, the script renders
BANDS x SPP bands of one sample per pixel each (`bands`), so the image
tends to the dispersive one as the samples grow.

For each SPP (samples per pixel of every band) it writes OUT_DIR/xyz-SPP.f32
(the image's CIE XYZ, little-endian float32, rows from the top, X Y Z per
pixel) and prints one line `SPP SECONDS`: the seconds of the render calls
alone, summed over the bands (the scenes are loaded before the clock
starts, as refract's scene is built before its clock starts).
"""

import json
import os
import sys
import time

import numpy as np


def band_scene(mi, s, lo, hi, centroid):
    """The scene of one band [lo, hi) nm, as a dict for mi.load_dict."""
    nm = np.array(s["spectrum"]["nm"], dtype=float)
    val = np.array(s["spectrum"]["values"], dtype=float)
    # The light's spectrum inside the band, zero outside (a step at each end).
    eps = 1e-3
    inside = (nm > lo) & (nm < hi - eps)
    wl = [lo - eps, lo] + list(nm[inside]) + [hi - eps, hi]
    v = [0.0, float(np.interp(lo, nm, val))] + list(val[inside]) + [float(np.interp(hi - eps, nm, val)), 0.0]
    um = centroid * 1e-3
    n = s["cauchy"]["a"] + s["cauchy"]["b_um2"] / (um * um)
    cam = s["camera"]
    beam = s["beam"]
    r = beam["radius"]
    d = beam["dir"]
    # The beam: a disc of radius r at its centre, emitting along its normal only.
    to_disc = mi.ScalarTransform4f().look_at(origin=beam["centre"], target=[beam["centre"][i] + d[i] for i in range(3)], up=beam["up"]).scale([r, r, 1.0])
    return {
        "type": "scene",
        "integrator": {"type": "ptracer", "max_depth": s["max_depth"], "hide_emitters": True},
        "sensor": {
            "type": "perspective",
            "fov": cam["vfov_deg"],
            "fov_axis": "y",
            "to_world": mi.ScalarTransform4f().look_at(origin=cam["pos"], target=cam["target"], up=cam["up"]),
            "film": {"type": "hdrfilm", "width": s["width"], "height": s["height"], "pixel_format": "xyz", "rfilter": {"type": "box"}},
            "sampler": {"type": "independent", "sample_count": 1},
        },
        "prism": {
            "type": "obj",
            "filename": s["prism_obj"],
            "face_normals": True,
            "bsdf": {"type": "dielectric", "int_ior": float(n), "ext_ior": 1.0},
        },
        "screen": {
            "type": "obj",
            "filename": s["screen_obj"],
            "face_normals": True,
            "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": s["albedo"]}},
        },
        "beam": {
            "type": "disk",
            "to_world": to_disc,
            "emitter": {"type": "directionalarea", "radiance": {"type": "irregular", "wavelengths": ", ".join(map(str, wl)), "values": ", ".join(map(str, v))}},
        },
    }


def bands(s, n):
    """n bands [lo, hi) nm tiling the spectrum's range, each of an equal
    share of half the light as the eye weighs it (`weight`: spectrum times
    x + y + z) plus half an even spread over the range, so that no band is
    wide where the light is dim; and each band's centroid under the weight."""
    nm = np.array(s["spectrum"]["nm"], dtype=float)
    w = np.array(s["spectrum"]["weight"], dtype=float)
    # Where the light is seen at all.
    lit = np.nonzero(w > 0)[0]
    nm, w = nm[lit[0] : lit[-1] + 1], w[lit[0] : lit[-1] + 1]
    mix = 0.5 * w / w.sum() + 0.5 / len(w)
    cdf = np.concatenate([[0.0], np.cumsum(0.5 * (mix[1:] + mix[:-1]))])
    cdf /= cdf[-1]
    edges = np.interp(np.linspace(0.0, 1.0, n + 1), cdf, nm)
    out = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        x = np.linspace(lo, hi, 17)
        wx = np.interp(x, nm, w)
        out.append((lo, hi, float((x * wx).sum() / wx.sum()) if wx.sum() > 0 else 0.5 * (lo + hi)))
    return out


def variant(mi):
    """Mitsuba's fastest spectral variant on the CPU: the vectorised,
    compiled `llvm_ad_spectral` where an LLVM it can use (16 or newer) is
    found, else `scalar_spectral`."""
    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        for v in (21, 20, 19, 18, 17, 16):
            path = f"/usr/lib/x86_64-linux-gnu/libLLVM-{v}.so"
            if os.path.exists(path):
                os.environ["DRJIT_LIBLLVM_PATH"] = path
                break
    if "DRJIT_LIBLLVM_PATH" in os.environ:
        try:
            mi.set_variant("llvm_ad_spectral")
            return "llvm_ad_spectral"
        except Exception:
            pass
    return "scalar_spectral"


def main():
    scene_path, out_dir, spps = sys.argv[1], sys.argv[2], [int(x) for x in sys.argv[3].split(",")]
    with open(scene_path) as f:
        s = json.load(f)
    import mitsuba as mi

    mi.set_variant(variant(mi))
    print(f"mitsuba {mi.__version__} {mi.variant()}", flush=True)
    for spp in spps:
        # spp passes of one sample per pixel, each pass in its own bands:
        # the bands (and the indices) grow finer as the samples grow.
        scenes = [mi.load_dict(band_scene(mi, s, lo, hi, c)) for lo, hi, c in bands(s, s["bands"] * spp)]
        total = None
        seconds = 0.0
        for k, scene in enumerate(scenes):
            t = time.perf_counter()
            img = mi.render(scene, spp=1, seed=100000 * spp + k)
            img = np.array(img, dtype=np.float64)
            seconds += time.perf_counter() - t
            total = img if total is None else total + img
        xyz = np.ascontiguousarray(total[:, :, :3], dtype="<f4")
        if not np.all(np.isfinite(xyz)):
            sys.exit(f"mitsuba: the image at {spp} spp holds NaN or infinite values")
        xyz.tofile(f"{out_dir}/xyz-{spp}.f32")
        print(f"{spp} {seconds:.6f}", flush=True)


if __name__ == "__main__":
    main()
