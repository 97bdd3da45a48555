# Builds one of restir's scenes in Blender Cycles and renders it to a linear float EXR, with
# settings under which Cycles and `restir render --method pt` estimate the same image.
# For our own checks only: no part of `make` or `make test` runs Blender. Written for the
# Debian package Blender 3.4.1 (Cycles 3.4); docs/environment.md "Against Blender Cycles"
# derives every conversion used below, tools/cycles/README.md says how to run it.
#
#   blender -b --factory-startup -noaudio --python-exit-code 1 \
#       -P tools/cycles/restir_to_cycles.py -- SCENE OUT.exr --restir build/restir \
#       [--samples 256] [--seed 1] [--max-depth 10] [--threads 1] [--srgb-node 0]
#
# What it reads: the scene file's mesh, camera, size, environment and sun lines (nothing else
# may be needed: keyframes, animate, light lines are refused), the OBJ's v/f/usemtl lines, and
# the materials as restir itself resolved them (`restir info SCENE`), so the MTL rules are not
# re-implemented here. Only what maps exactly is accepted: Lambertian materials without
# emission, optionally with a `map_Kd` colour map (read from the OBJ's MTL files: the
# statement and the OBJ's vt and f v/vt corners). Anything else stops the script with a
# message. A map's texels are decoded by restir itself (`restir merge` writes the linear
# float texels PNG colour maps decode to) and given to Cycles as a float image in the Linear
# colour space, times Kd: Cycles then interpolates linear values as we do (docs/environment.md
# 8.6; `--srgb-node 1` instead loads the PNG as an sRGB image, which Cycles interpolates
# before decoding: for measuring that difference only).

import math
import os
import shlex
import subprocess
import sys
import tempfile

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "scripts", "results"))
from relmse_channels import read_pfm as read_pfm_flat  # noqa: E402  (one PFM reader)


def fail(msg):
    sys.stderr.write("restir_to_cycles: %s\n" % msg)
    sys.exit(2)


def to_blender(p):
    """Our frame is +y up; Blender's is +z up. (x, y, z) -> (x, -z, y) is the proper rotation
    by +90 degrees about x, so handedness and every right-handed rotation are kept."""
    return Vector((p[0], -p[2], p[1]))


# ---------------------------------------------------------------- arguments


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    opts = {"samples": 256, "seed": 1, "max-depth": 10, "threads": 1,
            "restir": "build/restir", "srgb-node": 0}
    pos = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a.startswith("--"):
            key = a[2:]
            if key not in opts or i + 1 >= len(argv):
                fail("unknown option or missing value: %s" % a)
            opts[key] = type(opts[key])(argv[i + 1])
            i += 2
        else:
            pos.append(a)
            i += 1
    if len(pos) != 2:
        fail("usage: ... -- SCENE OUT.exr [--restir BIN] [--samples N] [--seed S] "
             "[--max-depth D] [--threads T] [--srgb-node 0|1]")
    if opts["max-depth"] < 2:
        fail("--max-depth must be >= 2 (Cycles' 0 bounces is our depth 2)")
    return pos[0], pos[1], opts


# ---------------------------------------------------------------- scene file


def read_scene(path):
    sc = {"meshes": [], "camera": None, "size": (512, 512), "env": None, "sun": None}
    base = os.path.dirname(os.path.abspath(path))
    with open(path) as f:
        for lineno, line in enumerate(f, 1):
            toks = shlex.split(line, comments=True)
            if not toks:
                continue
            d, args = toks[0], toks[1:]
            where = "%s:%d" % (path, lineno)
            if d == "mesh":
                sc["meshes"].append(os.path.join(base, args[0]))
            elif d == "camera":
                kv = {}
                j = 0
                while j < len(args):
                    n = 1 if args[j] == "fov" else 3
                    kv[args[j]] = [float(x) for x in args[j + 1:j + 1 + n]]
                    j += 1 + n
                sc["camera"] = kv
            elif d == "size":
                sc["size"] = (int(args[0]), int(args[1]))
            elif d == "environment":
                if args[0] == "constant":
                    sc["env"] = ("constant", [float(x) for x in args[1:4]])
                else:
                    rot, scale, j = 0.0, 1.0, 2
                    while j < len(args):
                        if args[j] == "rotate":
                            rot = float(args[j + 1])
                        elif args[j] == "scale":
                            scale = float(args[j + 1])
                        else:
                            fail("%s: unknown environment key %s" % (where, args[j]))
                        j += 2
                    sc["env"] = ("map", os.path.join(base, args[1]), rot, scale)
            elif d == "sun":
                v = [float(x) for x in args]
                sc["sun"] = (v[0:3], v[3], v[4:7])
            elif d == "material":
                pass  # resolved by `restir info` (read_materials)
            else:
                fail("%s: '%s' cannot be built in Cycles by this script" % (where, d))
    if sc["camera"] is None:
        fail("%s: needs a camera line (the framing camera is not reproduced)" % path)
    return sc


def read_materials(restir, scene_path):
    """The materials after restir's MTL rules and the scene file's material lines."""
    try:
        out = subprocess.run([restir, "info", scene_path], check=True, stdout=subprocess.PIPE,
                             universal_newlines=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        fail("could not run '%s info %s': %s" % (restir, scene_path, e))
    mats = {}
    for line in out.splitlines():
        t = line.split()
        if len(t) < 2 or t[0] != "material":
            continue
        # material NAME TYPE kd (r g b) ks (...) ke (...) roughness R ior N; NAME has no blanks
        # in the scenes this script is meant for (a quoted name with blanks is refused)
        text = line.replace("(", " ").replace(")", " ").split()
        try:
            name, kind = text[1], text[2]
            kd = [float(x) for x in text[4:7]]
            ke = [float(x) for x in text[12:15]]
        except (IndexError, ValueError):
            fail("cannot read this `restir info` material line: %s" % line.strip())
        if kind != "lambert":
            fail("material '%s' is %s: only Lambertian materials map exactly onto Cycles "
                 "(make it `type lambert` in a scene file of its own)" % (name, kind))
        if max(ke) > 0:
            fail("material '%s' emits: emitters are not built by this script" % name)
        mats[name] = kd
    return mats


def read_mtl_maps(obj_path, mtllibs):
    """map_Kd file of each material of the OBJ's MTL files (the statements restir reads);
    refuses the maps that would not map exactly onto a Diffuse BSDF."""
    maps = {}
    base = os.path.dirname(os.path.abspath(obj_path))
    for lib in mtllibs:
        path = os.path.join(base, lib)
        cur = None
        with open(path) as f:
            for lineno, line in enumerate(f, 1):
                t = line.split("#", 1)[0].split()
                if not t:
                    continue
                where = "%s:%d" % (path, lineno)
                if t[0] == "newmtl":
                    cur = line.split(None, 1)[1].strip()
                elif t[0] == "map_Kd":
                    if len(t) != 2 or t[1].startswith("-"):
                        fail("%s: map_Kd with options or blanks is not built" % where)
                    maps[cur] = os.path.join(os.path.dirname(path), t[1])
                elif t[0] in ("map_Ke", "map_d", "map_Pr", "map_Ns"):
                    fail("%s: %s does not map exactly onto a Diffuse BSDF (only map_Kd is "
                         "built)" % (where, t[0]))
    return maps


def read_obj(path):
    """Triangles (fans of the OBJ polygons, as restir's triangulation of convex faces), the
    material name of each, the UVs of each triangle's corners (None: no vt on all three
    corners, which restir reads as UV (0, 0)), and the OBJ's mtllib files."""
    verts, uvs, tris, tri_uv, mat_of, cur, libs = [], [], [], [], [], None, []
    with open(path) as f:
        for line in f:
            t = line.split("#", 1)[0].split()
            if not t:
                continue
            if t[0] == "v":
                verts.append([float(x) for x in t[1:4]])
            elif t[0] == "vt":
                uvs.append((float(t[1]), float(t[2]) if len(t) > 2 else 0.0))
            elif t[0] == "f":
                idx, tidx = [], []
                for w in t[1:]:
                    parts = w.split("/")
                    i = int(parts[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                    if len(parts) > 1 and parts[1]:
                        j = int(parts[1])
                        tidx.append(j - 1 if j > 0 else len(uvs) + j)
                    else:
                        tidx.append(None)
                for k in range(1, len(idx) - 1):
                    tris.append((idx[0], idx[k], idx[k + 1]))
                    c = (tidx[0], tidx[k], tidx[k + 1])
                    tri_uv.append(None if None in c else tuple(uvs[j] for j in c))
                    mat_of.append(cur)
            elif t[0] == "usemtl":
                cur = line.split(None, 1)[1].strip()
            elif t[0] == "mtllib":
                libs.extend(t[1:])
    return verts, tris, mat_of, tri_uv, libs


def decoded_texels(restir, path):
    """The map's texels as restir decodes a colour map (sRGB EOTF for PNG, EXR/PFM as
    stored; grey to RGB): `restir merge` of one image with count 1 writes them as a PFM."""
    fd, tmp = tempfile.mkstemp(suffix=".pfm")
    os.close(fd)
    try:
        subprocess.run([restir, "merge", "-o", tmp, path, "--counts", "1", "--no-png", "--quiet"],
                       check=True)
        return read_pfm_flat(tmp)  # rows bottom to top, as Blender's pixel buffer
    except (OSError, subprocess.CalledProcessError) as e:
        fail("could not decode %s with '%s merge': %s" % (path, restir, e))
    finally:
        os.unlink(tmp)


def texture_node(nt, path, kd, opts):
    """An Image Texture node giving Kd * map at the surface's UV, bilinear with repeat
    (docs/environment.md 8.6: Cycles' Linear lookup with Repeat is our lookup), or with
    --srgb-node 1 the PNG as Blender loads it in the sRGB colour space (Kd by a multiply)."""
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.interpolation = "Linear"
    tex.extension = "REPEAT"
    tex.projection = "FLAT"
    uv = nt.nodes.new("ShaderNodeTexCoord")
    nt.links.new(uv.outputs["UV"], tex.inputs["Vector"])
    if opts["srgb-node"]:
        img = bpy.data.images.load(os.path.abspath(path))
        img.colorspace_settings.name = "sRGB"
        tex.image = img
        mul = nt.nodes.new("ShaderNodeMixRGB")
        mul.blend_type = "MULTIPLY"
        mul.inputs["Fac"].default_value = 1.0
        mul.inputs["Color1"].default_value = (kd[0], kd[1], kd[2], 1.0)
        nt.links.new(tex.outputs["Color"], mul.inputs["Color2"])
        return mul.outputs["Color"]
    w, h, px = decoded_texels(opts["restir"], path)
    img = bpy.data.images.new(os.path.basename(path), width=w, height=h, alpha=True,
                              float_buffer=True)
    img.colorspace_settings.name = "Linear"
    rgba = []
    for i in range(w * h):
        rgba.extend((px[3 * i] * kd[0], px[3 * i + 1] * kd[1], px[3 * i + 2] * kd[2], 1.0))
    img.pixels = rgba
    tex.image = img
    return tex.outputs["Color"]


# ---------------------------------------------------------------- building


def build_mesh(sc, mats, opts):
    for mi, path in enumerate(sc["meshes"]):
        verts, tris, mat_of, tri_uv, libs = read_obj(path)
        maps = read_mtl_maps(path, libs)
        names = sorted(set(mat_of), key=lambda n: (n is None, n or ""))
        me = bpy.data.meshes.new("mesh%d" % mi)
        me.from_pydata([tuple(to_blender(v)) for v in verts], [], tris)
        if any(n in maps for n in names):
            layer = me.uv_layers.new(name="UVMap")
            for poly, corners in zip(me.polygons, tri_uv):
                for k, li in enumerate(poly.loop_indices):
                    layer.data[li].uv = corners[k] if corners else (0.0, 0.0)
        for n in names:
            kd = mats.get(n) if n is not None else None
            if kd is None:
                fail("%s: material %s not in `restir info`" % (path, n))
            m = bpy.data.materials.new(n)
            m.use_nodes = True
            nt = m.node_tree
            nt.nodes.clear()
            out = nt.nodes.new("ShaderNodeOutputMaterial")
            bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
            bsdf.inputs["Color"].default_value = (kd[0], kd[1], kd[2], 1.0)
            if n in maps:
                nt.links.new(texture_node(nt, maps[n], kd, opts), bsdf.inputs["Color"])
            bsdf.inputs["Roughness"].default_value = 0.0  # Oren-Nayar off: Lambert
            nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
            me.materials.append(m)
        slot = {n: i for i, n in enumerate(names)}
        for poly, n in zip(me.polygons, mat_of):
            poly.material_index = slot[n]
            poly.use_smooth = False  # flat: restir has no vn in these OBJs
        me.validate()
        me.update()
        ob = bpy.data.objects.new("mesh%d" % mi, me)
        bpy.context.scene.collection.objects.link(ob)


def build_camera(sc):
    c = sc["camera"]
    eye, target, up = Vector(c["eye"]), Vector(c["target"]), Vector(c["up"])
    fwd = (target - eye).normalized()
    right = fwd.cross(up).normalized()  # gluLookAt: right = forward x up
    up2 = right.cross(fwd)
    # Blender's camera looks along its local -Z with +Y up and +X right.
    cols = [to_blender(right), to_blender(up2), to_blender(-fwd)]
    rot = Matrix([[cols[j][i] for j in range(3)] for i in range(3)])
    cam = bpy.data.cameras.new("camera")
    cam.type = "PERSP"
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(c["fov"][0])
    size = max(abs(x) for x in eye) + 1.0
    cam.clip_start = 1e-5 * size
    cam.clip_end = 1e6 * size
    ob = bpy.data.objects.new("camera", cam)
    ob.matrix_world = Matrix.Translation(to_blender(eye)) @ rot.to_4x4()
    bpy.context.scene.collection.objects.link(ob)
    bpy.context.scene.camera = ob


def build_world(sc):
    world = bpy.data.worlds.new("world")
    bpy.context.scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputWorld")
    bg = nt.nodes.new("ShaderNodeBackground")
    bg.inputs["Strength"].default_value = 1.0
    nt.links.new(bg.outputs["Background"], out.inputs["Surface"])
    env = sc["env"]
    if env is None:
        bg.inputs["Color"].default_value = (0, 0, 0, 1)
        bg.inputs["Strength"].default_value = 0.0
    elif env[0] == "constant":
        r, g, b = env[1]
        bg.inputs["Color"].default_value = (r, g, b, 1.0)
    else:
        _, path, rot_deg, scale = env
        w, h, px = read_pfm_flat(path)  # rows bottom to top, as Blender's pixel buffer
        img = bpy.data.images.new("sky", width=w, height=h, alpha=True, float_buffer=True)
        img.colorspace_settings.name = "Linear"
        rgba = []
        for i in range(w * h):
            rgba.extend((px[3 * i] * scale, px[3 * i + 1] * scale, px[3 * i + 2] * scale, 1.0))
        img.pixels = rgba
        tex = nt.nodes.new("ShaderNodeTexEnvironment")
        tex.image = img
        tex.interpolation = "Closest"  # restir's map is piecewise constant (one texel)
        tex.projection = "EQUIRECTANGULAR"
        coord = nt.nodes.new("ShaderNodeTexCoord")
        mapping = nt.nodes.new("ShaderNodeMapping")
        mapping.vector_type = "VECTOR"
        # docs/environment.md "Against Blender Cycles": Cycles reads texel (u, v) from the
        # direction M w with M = Rz(90 deg + rotate) diag(1, -1, 1) in Blender's frame.
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(90.0 + rot_deg))
        mapping.inputs["Scale"].default_value = (1.0, -1.0, 1.0)
        nt.links.new(coord.outputs["Object"], mapping.inputs["Vector"])
        nt.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        nt.links.new(tex.outputs["Color"], bg.inputs["Color"])
    world.cycles.sampling_method = "MANUAL"
    world.cycles.sample_map_resolution = 1024
    world.cycles.max_bounces = 1024


def build_sun(sc):
    if sc["sun"] is None:
        return
    d, angle_deg, rad = sc["sun"]
    a = math.radians(angle_deg)
    # Cycles 3.4's sun: radiance S / (pi tan^2 a cos^3 t) inside the cone of half-angle a,
    # whose solid-angle integral is S. Ours: uniform L in the same cone, integral
    # L * 2 pi (1 - cos a) = 4 pi sin^2(a/2) L. Equal integrals (docs/environment.md).
    omega = 4.0 * math.pi * math.sin(a / 2) ** 2
    strength = [omega * x for x in rad]
    energy = max(strength)
    light = bpy.data.lights.new("sun", type="SUN")
    light.energy = energy
    light.color = [x / energy for x in strength] if energy > 0 else (0, 0, 0)
    light.angle = 2.0 * a  # Blender's angle is the full angular diameter
    light.cycles.cast_shadow = True
    light.cycles.use_multiple_importance_sampling = True
    light.cycles.max_bounces = 1024
    ob = bpy.data.objects.new("sun", light)
    s = to_blender(Vector(d).normalized())
    # the lamp shines along its local -Z: +Z points towards the sun
    ob.rotation_euler = s.to_track_quat("Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(ob)


def configure(scene, sc, opts, out_path):
    r = scene.render
    r.engine = "CYCLES"
    r.resolution_x, r.resolution_y = sc["size"]
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.use_compositing = False
    r.use_sequencer = False
    r.threads_mode = "FIXED"
    r.threads = opts["threads"]
    r.filepath = out_path
    r.use_file_extension = False
    im = r.image_settings
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGB"
    im.color_depth = "32"
    im.exr_codec = "ZIP"
    c = scene.cycles
    c.device = "CPU"
    c.samples = opts["samples"]
    c.seed = opts["seed"]
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    # the 3.4 defaults, pinned: progressive multi-jitter, fully scrambled per seed (runs with
    # different seeds are independent randomisations)
    c.sampling_pattern = "PROGRESSIVE_MULTI_JITTER"
    c.scrambling_distance = 1.0
    c.auto_scrambling_distance = False
    c.use_denoising = False
    c.use_preview_denoising = False
    bounces = opts["max-depth"] - 2  # our path length d <= D is Cycles' bounces <= D - 2
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = bounces
    c.transmission_bounces = bounces
    c.volume_bounces = 0
    c.transparent_max_bounces = 8
    c.min_light_bounces = bounces  # Russian roulette off (ours is off by default)
    c.min_transparent_bounces = 8
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.light_sampling_threshold = 0.0
    c.use_fast_gi = False
    c.ao_bounces = 0
    c.ao_bounces_render = 0
    c.film_exposure = 1.0
    # Cycles 3.4's Box filter is always one pixel wide (filter_width applies to the other
    # types only; measured: widths 0.01 and 1 give identical images): uniform over the pixel,
    # which is `restir render --jitter`.
    c.pixel_filter_type = "BOX"
    v = scene.view_settings
    v.view_transform = "Standard"
    v.look = "None"
    v.exposure = 0.0
    v.gamma = 1.0


def main():
    scene_path, out_path, opts = parse_args()
    sc = read_scene(scene_path)
    mats = read_materials(opts["restir"], scene_path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    build_mesh(sc, mats, opts)
    build_camera(sc)
    build_world(sc)
    build_sun(sc)
    configure(scene, sc, opts, os.path.abspath(out_path))
    bpy.ops.render.render(write_still=True)
    print("restir_to_cycles: wrote %s (Blender %s, %d samples, seed %d, bounces %d, box 1 px)"
          % (out_path, bpy.app.version_string, opts["samples"], opts["seed"],
             opts["max-depth"] - 2))


main()
