"""GLSL sources for the scene renderer.

One vertex/fragment pair, specialised per drawable style with ``#define``s, so
each compiled program carries only the code its style needs (llvmpipe runs
fragment shaders on the CPU: every instruction counts at 1280x720).

What llvmpipe charges for, measured over a full 1280x720 view (CPU ms of all its threads):
reading a uniform in a fragment shader (lane by lane, with a bounds check; about 0.25 ms per
component), ``exp`` and ``pow`` (about 1 ms each), and every branch's body (a branch only masks
lanes). So the vertex shader reads every uniform and hands the fragment shader flat inputs
(the eye, the light, the w cue of a 4D thing), and fog and highlights use a few multiplies
instead of ``exp`` and ``pow`` (within 0.02 of them). A flat input is not free either: llvmpipe
sets up every input of every triangle and stores it with the triangle's bin, so each one costs
per triangle (four fewer took 2 ms off a hundred sliced 120-cells, 20,000 triangles). The
palette's light colours, which change only with the settings, are therefore compiled into the
fragment shader as constants (:func:`program_source`), one build of the programs per palette.
The level's boxes and the sections of 4D worlds have one normal a triangle, so what depends on
the normal alone (the side facing the eye, the plane of the panels or of the w bands, the
ambient and diffuse light) is the same over a face: a program of their own works it out per
vertex (``FACETED``; 7-9 % of the scenery's shading, 3-4 % of 4D matter's).

Colour pipeline: vertex colours are linear RGB; lighting happens in linear
space; the result goes through a soft shoulder (so highlights don't clip
harshly) and a gamma of 2 (``sqrt``: close to sRGB's ~2.2 and cheaper than
``pow`` when llvmpipe runs the shader on the CPU); fog then mixes toward the
sky colour, which is a *display* colour (the framebuffer is cleared with it
unchanged), so distant surfaces fade exactly into the sky.
"""

from __future__ import annotations

from collections.abc import Mapping

from . import materials

#: The sky dome's colour by view direction (display space): ground below the horizon, a
#: bright horizon band, the zenith above. Shared by the sky and by fog, so fog fades a
#: distant wall into exactly the sky behind it.
SKY_GRADIENT = """
vec3 sky_gradient(vec3 d) {
    float y = d.y;
    vec3 up = mix(u_sky_horizon, u_sky_zenith, sqrt(clamp(y, 0.0, 1.0)));
    vec3 down = mix(u_sky_horizon, u_sky_ground, smoothstep(0.0, 0.2, -y));
    return y >= 0.0 ? up : down;
}
"""

#: Where the w bands and the lattice of 4D matter lie on a surface (the vertex shader's, per
#: vertex, for faceted meshes; else the fragment shader's).
MATTER_COORDS = """
// At ``p`` on a surface whose normal has magnitudes ``an``: x across the w bands (levels of
// height on vertical faces, diagonals on horizontal ones), y along them, zw the lattice's
// diagonal grid on the plane the surface faces.
vec4 matter_coords(vec3 an, vec3 p) {
    float s = an.y > 0.7 ? (p.x + p.z) * 0.7071 : p.y;
    float u = an.x > an.z ? p.z : p.x;
    vec2 huv = an.y > 0.7 ? p.xz : (an.x > an.z ? p.zy : p.xy);
    return vec4(s, u, vec2(huv.x + huv.y, huv.x - huv.y) * 2.0);
}
"""

VERTEX = """
uniform mat4 u_view_proj;
uniform mat4 u_model;
uniform mat3 u_normal_mat;
uniform vec3 u_eye;
uniform vec3 u_light_dir;   // toward the light, normalised on the CPU
uniform float u_fog_density;

in vec3 in_pos;
in vec3 in_normal;
in vec4 in_color;

out vec3 v_world;
out vec3 v_normal;
out vec4 v_color;
#ifdef FACETED
// A mesh whose every triangle has one normal (boxes, sections of 4D worlds): what depends on the normal
// alone is the same over a face and is worked out here, per vertex, instead of per pixel.
// xyz the normal of the side facing the eye, w 1 on walls (0 on floors and ceilings).
flat out vec4 v_face;
// rgb the hemisphere ambient plus the sun's diffuse light, w the diffuse factor.
flat out vec4 v_face_light;
// Coordinates linear in the position over a plane, so interpolated exactly: the panels' of
// scenery, or where the w bands and the lattice of 4D matter lie (see matter_coords).
  #ifdef STYLE_HYPER
out vec4 v_planes;
MATTER_COORDS
  #else
out vec2 v_panel;
  #endif
#endif
// What is the same for every pixel and changes every frame goes to the fragment shader as
// flat varyings, not uniforms: llvmpipe reads a uniform in a fragment shader lane by lane,
// with a bounds check (about 0.25 ms of CPU per component over a full 1280x720 view), a flat
// input once a triangle. xyz the eye and the light; w the fog's density squared, and the
// trims' pulse (the crystals' own in theirs, a ghost's opacity in the ghosts'). The
// palette's colours are the fragment shader's constants (see program_source).
flat out vec4 v_eye;
flat out vec4 v_sun;
#ifdef LOOK_SCIFI
uniform float u_time;
uniform float u_pulse;      // the trims' slow breathing, 0.8 to 1 (set once a frame)
uniform vec3 u_sky_zenith;  // display colours of the sky dome (fog goes to its horizon)
uniform vec3 u_sky_horizon;
uniform vec3 u_sky_ground;
// xyz the sky behind the vertex (smooth, so per vertex is enough); w the iridescence's drift
// of 4D matter, or a ghost's pattern, the same at every vertex: an input of its own would
// cost every triangle's setup.
out vec4 v_fog_color;
SKY_GRADIENT
#else
uniform vec3 u_sky;         // display-space sky colour (fog target)
flat out vec4 v_fog_color;  // xyz that colour, w as in the sci-fi look
#endif
#if defined(LOOK_SCIFI) && (defined(STYLE_HYPER) || defined(STYLE_GLOW))
uniform float u_glow_pulse; // the crystals' faster pulse (set once a frame; v_sun.w in their program)
uniform float u_w_offset;
uniform float u_band_scale;
uniform float u_w_from_alpha;
// The w cue's parameters, one thing's throughout (its w offset is a uniform, or every vertex
// of a batched thing carries the same one): x bands per metre, y their drift, z the side
// (1 ana, -1 kata), w their strength.
flat out vec4 v_band;
#endif
#ifdef STYLE_GHOST
uniform float u_alpha;      // ghost opacity
uniform vec4 u_tint;        // rgb the ghost's colour is pulled to, and how far (a)
uniform int u_pattern;      // 0 plain, 1 stripes, 2 dots (screen space)
uniform float u_opacity;    // per-drawable factor (fading along w, preview emphasis)
flat out vec4 v_tint;
#endif

void main() {
    vec4 world = u_model * vec4(in_pos, 1.0);
    v_world = world.xyz;
    v_eye = vec4(u_eye, u_fog_density * u_fog_density);
    v_sun = vec4(u_light_dir, 0.0);
#ifdef LOOK_SCIFI
    v_fog_color = vec4(sky_gradient(normalize(world.xyz - u_eye)), 0.05 * u_time);
  #ifdef STYLE_GLOW
    v_sun.w = u_glow_pulse;
  #else
    v_sun.w = u_pulse;
  #endif
#else
    v_fog_color = vec4(u_sky, 0.0);
#endif
#if defined(LOOK_SCIFI) && (defined(STYLE_HYPER) || defined(STYLE_GLOW))
    // Bands whose spacing shrinks as the slice nears the edge of the thing along w (see
    // w_bands in the fragment shader): sparse and faint at its centre, dense at the edge.
    float w_off = u_w_from_alpha > 0.5 ? in_color.a : u_w_offset;
    float a = min(abs(w_off), 1.0);
    float side = w_off >= 0.0 ? 1.0 : -1.0;
    float period = u_band_scale * mix(0.9, 0.14, a);
    // No bands right at the centre (nothing to warn about).
    v_band = vec4(1.0 / period, side * u_time * (0.25 + 0.9 * a), side, smoothstep(0.06, 0.22, a));
#endif
#ifdef STYLE_GHOST
    v_tint = u_tint;
    v_sun.w = u_alpha * u_opacity;  // the ghost's opacity
    v_fog_color.w = float(u_pattern);
#endif
    v_normal = u_normal_mat * in_normal;
    v_color = in_color;
#ifdef FACETED
    // The eye is on one side of a face's plane at all its vertices, so the side facing it
    // (two-sided lighting) is found here once.
    vec3 n = normalize(v_normal);
    n = dot(n, u_eye - world.xyz) < 0.0 ? -n : n;
    vec3 an = abs(n);
    bool level_face = an.y >= max(an.x, an.z);
    v_face = vec4(n, level_face ? 0.0 : 1.0);
  #ifdef STYLE_HYPER
    v_planes = matter_coords(an, world.xyz);
  #else
    v_panel = level_face ? world.xz * 0.5 : (an.x >= an.z ? world.zy : world.xy) * vec2(1.0 / 1.5, 1.0);
  #endif
    float diffuse = max(dot(n, u_light_dir), 0.0);
    v_face_light = vec4(AMBIENT + AMBIENT_UP * n.y + diffuse * KEY_LIGHT, diffuse);
#endif
    gl_Position = u_view_proj * world;
#ifdef STYLE_WIRE
    // Pull lines slightly toward the camera so an outline drawn over a solid
    // with the same geometry wins the depth test instead of z-fighting.
    gl_Position.z -= 2e-4 * gl_Position.w;
#endif
}
""".replace("SKY_GRADIENT", SKY_GRADIENT).replace("MATTER_COORDS", MATTER_COORDS)

FRAGMENT = """
in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;
#ifdef FACETED
flat in vec4 v_face;        // the normal facing the eye, w 1 on walls (see the vertex shader)
flat in vec4 v_face_light;  // ambient plus diffuse sunlight, w the diffuse factor
  #ifdef STYLE_HYPER
in vec4 v_planes;           // where the w bands and the lattice lie (see matter_coords)
  #else
in vec2 v_panel;
  #endif
#endif
flat in vec4 v_eye;         // xyz the eye, w the fog's density squared
flat in vec4 v_sun;         // xyz toward the light, w the pulse or a ghost's opacity (see the vertex shader)
#ifdef LOOK_SCIFI
in vec4 v_fog_color;       // xyz the sky behind, w the iridescence's drift or the ghost's pattern
#else
flat in vec4 v_fog_color;
#endif
#if defined(LOOK_SCIFI) && (defined(STYLE_HYPER) || defined(STYLE_GLOW))
flat in vec4 v_band;        // the w cue, per thing (see the vertex shader)
#endif
#ifdef STYLE_GHOST
flat in vec4 v_tint;
#endif

out vec4 f_color;

// llvmpipe runs this on the CPU, every branch of it for every pixel (a branch only masks
// lanes), at about 30 cycles a millisecond of a full 1280x720 view: what does not vary per
// pixel is worked out per vertex, uniforms are read there, and exp, pow and divisions are
// avoided.

vec3 to_display(vec3 c) {
    // Linear up to 0.8, then a soft shoulder approaching 1.0.
    c = max(c, 0.0);
    vec3 over = max(c - 0.8, 0.0);
    // (A rational shoulder: the same slope and limit as 0.2 * (1 - exp(-over / 0.2)), no exp.)
    c = min(c, 0.8) + over / (1.0 + 5.0 * over);
    return sqrt(c);
}

// exp(-x) for x >= 0 as (1 - x/32)^32, within 0.009: five multiplies instead of exp's
// polynomial and exponent bits.
float exp_neg(float x) {
    float e = max(1.0 - x * (1.0 / 32.0), 0.0);
    e *= e; e *= e; e *= e; e *= e;
    return e * e;
}

#if !defined(STYLE_WIRE) && !defined(STYLE_GHOST) && !defined(STYLE_GLOW)
// pow(x, n) near its highlight: x^n = exp(n ln x), with ln x ~ -(1 - x)(1 + (1 - x) / 2)
// and exp(-m) ~ (1 - m/16)^16; within 0.018 of pow for any n (a highlight is at most 0.45).
float pow_highlight(float x, float n) {
    float u = 1.0 - x;
    float e = max(1.0 - n * u * (1.0 + 0.5 * u) * (1.0 / 16.0), 0.0);
    e *= e; e *= e; e *= e;
    return e * e;
}
#endif

#ifdef LOOK_SCIFI
// A hash without sin (Hoskins): a few multiplies, cheaper than sin on llvmpipe.
float hash12(vec2 p) {
    vec3 p3 = fract(vec3(p.xyx) * 0.1031);
    p3 += dot(p3, p3.yzx + 33.33);
    return fract((p3.x + p3.y) * p3.z);
}

#endif

#ifdef STYLE_FLOOR
float grid_lines(vec2 uv, float spacing) {
    vec2 p = uv / spacing;
    vec2 fw = max(fwidth(p), vec2(1e-6));
    // Distance to the nearest line in pixels -> ~1 px wide anti-aliased lines.
    vec2 g = abs(fract(p - 0.5) - 0.5) / fw;
    float line = 1.0 - min(min(g.x, g.y), 1.0);
    // Fade out where cells shrink below a few pixels (distance, grazing angles)
    // instead of letting the lines alias into moire.
    return line * (1.0 - smoothstep(0.15, 0.5, max(fw.x, fw.y)));
}
#endif

#if defined(LOOK_SCIFI) && (defined(STYLE_HYPER) || defined(STYLE_GLOW))
MATTER_COORDS
// The w cue of 4D matter, in pattern and motion rather than colour: bands across the
// surface whose spacing shrinks as the slice nears the edge of the thing along w (sparse
// and faint at its centre, dense at the edge), solid lines rising when the thing lies ana
// (+w) of the slice and dotted lines sinking when it lies kata (-w), the same sides as
// the ghosts' stripes and dots. Returns the band mask in 0-1. ``su``: where the surface
// point lies across and along the bands (matter_coords).
float w_bands(vec2 su) {
    float t = su.x * v_band.x - v_band.y;
    float fw = max(fwidth(t), 1e-5);
    float rfw = 0.5 / fw;
    float d = abs(fract(t) - 0.5);  // 0.5 at a band's middle
    // Linear anti-aliasing over two pixels' worth of t either side of the edge.
    float band = clamp((d - 0.34) * rfw + 0.5, 0.0, 1.0);
    // kata: dotted, the dots as long as the bands are wide (computed on both sides: a branch
    // costs as much as its body on llvmpipe)
    float u = su.y * v_band.x;
    float du = abs(fract(u) - 0.5);
    float dots = clamp((du - 0.25) * (0.5 / max(fwidth(u), 1e-5)) + 0.5, 0.0, 1.0);
    band *= v_band.z < 0.0 ? dots : 1.0;
    // None where they would alias.
    return band * v_band.w * clamp(2.0 - 4.0 * fw, 0.0, 1.0);
}
#endif

#ifdef STYLE_GHOST
// Screen-space patterns, so the two sides of the slice differ in texture as well as
// hue (never colour alone) at any distance and on any surface. 1 on the pattern's
// marks, a faint floor between them so the ghost's shape still reads.
float ghost_pattern(vec2 px) {
    // The pattern's number, interpolated (the same at every vertex, so within rounding of it).
    float pattern = v_fog_color.w;
    if (abs(pattern - 1.0) < 0.5) {
        // Diagonal stripes, 9 px period, 4 px wide, anti-aliased by fwidth.
        float t = (px.x + px.y) / 9.0;
        float d = abs(fract(t) - 0.5) * 9.0;
        return 0.35 + 0.65 * (1.0 - smoothstep(1.5, 2.5, d));
    }
    if (abs(pattern - 2.0) < 0.5) {
        // Dots on an 8 px grid, radius 2.2 px.
        vec2 c = (fract(px / 8.0) - 0.5) * 8.0;
        return 0.35 + 0.65 * (1.0 - smoothstep(1.7, 2.7, length(c)));
    }
    return 1.0;
}
#endif

void main() {
    vec3 albedo = v_color.rgb;
#ifdef STYLE_GHOST
    albedo = mix(albedo, v_tint.rgb, v_tint.a);
#endif
    vec3 to_eye = v_eye.xyz - v_world;
    float dist2 = dot(to_eye, to_eye);
    vec3 V = to_eye * inversesqrt(max(dist2, 1e-12));
    vec3 emit = vec3(0.0);  // light of the surface's own, added after lighting

#ifdef STYLE_WIRE
    vec3 lit = albedo;
#elif defined(FACETED)
    vec3 N = v_face.xyz;
    float ndv = max(dot(N, V), 0.0);
    float gloss = 1.0;
#else
  #ifdef FLAT_NORMALS
    // A mesh without normals (a frustum projection) is shaded flat, with the face normal taken
    // from screen-space derivatives of the position. A program of its own: computed in every
    // program and thrown away where normals exist, that normal cost 7-9 % of the scenery's
    // shading (llvmpipe pays both sides of a select).
    vec3 N = cross(dFdx(v_world), dFdy(v_world));
  #else
    vec3 N = v_normal;
  #endif
    N *= inversesqrt(max(dot(N, N), 1e-30));
    // Two-sided lighting: no culling and a mirrored view matrix mean we may see
    // either side of a triangle, so light the side facing the eye.
    float ndv = dot(N, V);
    if (ndv < 0.0) { N = -N; ndv = -ndv; }
    vec3 an = abs(N);
    float gloss = 1.0;
#endif
#ifndef STYLE_WIRE

  #if defined(LOOK_SCIFI) && (defined(STYLE_SOLID) || defined(STYLE_FLOOR))
    // Scenery is plated: panels on the world plane the surface faces (1.5 x 1 m on
    // walls, 2 m on floors), each a little lighter or darker, with dark seams, and a
    // few vented panels. Cheap (no textures, no branches on the common path, linear
    // anti-aliasing instead of smoothstep) and stable in world space.
    #ifdef FACETED
    float wall = v_face.w;
    vec2 p = v_panel;
    #else
    bool flat_face = an.y >= max(an.x, an.z);
    float wall = flat_face ? 0.0 : 1.0;
    vec2 p = flat_face ? v_world.xz * 0.5 : (an.x >= an.z ? v_world.zy : v_world.xy) * vec2(1.0 / 1.5, 1.0);
    #endif
    vec2 cell = floor(p);
    vec2 rfw = 1.0 / max(fwidth(p), vec2(1e-5));  // pixels per panel, on each axis
    // Pixels to the nearest seam on each axis; seams ~1.5 px wide, fading out where panels
    // shrink below ~10 px (distance, grazing angles) instead of aliasing into moire.
    vec2 fp = fract(p);
    vec2 g = (0.5 - abs(fp - 0.5)) * rfw;
    float fade = clamp(4.0 - 13.0 / min(rfw.x, rfw.y), 0.0, 1.0);
    vec2 seams = clamp(1.5 - g, 0.0, 1.0) * fade;
    float h = hash12(cell + floor(v_world.y * 0.25) * 17.0);
    // Cool, darker steel than the level's colours say: the emissive trims and the 4D
    // matter are the brightest things in view, so the eye goes to them.
    albedo *= vec3(0.70, 0.74, 0.82) * ((0.84 + 0.3 * h) * (1.0 - 0.6 * max(seams.x, seams.y)));
    gloss = 0.5 + h;
    // A vent on a few wall panels: horizontal slats over the panel's middle.
    vec2 in_mid = step(abs(fp - 0.5), vec2(0.3, 0.2));
    float slat = clamp((abs(fract(p.y * 16.0) - 0.5) - 0.25) * (rfw.y * (1.0 / 16.0)) + 0.5, 0.0, 1.0);
    float vent = h > 0.95 ? wall : 0.0;
    albedo *= 1.0 - 0.55 * vent * in_mid.x * in_mid.y * slat;
    #ifdef STYLE_FLOOR
    // Lit lines every 10 m (every fifth seam): wayfinding at a glance, and scale.
    vec2 major = step(mod(floor(p + 0.5), 5.0), vec2(0.5)) * seams;
    emit += FLOOR_LINE * (0.9 * max(major.x, major.y));
    #else
    // An emissive trim a hand above the floor (y 0.10 to 0.16), breathing slowly, over a
    // dark kick plate; walls darken upward, away from the trim and the floor's bounce.
    float y = v_world.y;
    float rfy = 1.0 / max(fwidth(y), 1e-4);
    float trim = clamp((y - 0.10) * rfy + 0.5, 0.0, 1.0) * clamp((0.16 - y) * rfy + 0.5, 0.0, 1.0);
    float kick = clamp((0.10 - y) * rfy + 0.5, 0.0, 1.0);
    albedo *= 1.0 - wall * (0.5 * kick + 0.35 * clamp((y - 0.3) * (1.0 / 3.7), 0.0, 1.0));
    emit += TRIM * (v_sun.w * wall * trim);
    #endif
  #elif defined(STYLE_FLOOR)
    // Grid on the plane most facing the normal: world xz for floors.
    vec2 uv = an.y >= max(an.x, an.z) ? v_world.xz : (an.x >= an.z ? v_world.zy : v_world.xy);
    float minor = grid_lines(uv, 1.0);
    float major = grid_lines(uv, 10.0);
    albedo = mix(albedo, albedo * 0.35 + vec3(0.10, 0.16, 0.22), max(minor * 0.55, major));
  #endif

  #if defined(LOOK_SCIFI) && defined(STYLE_HYPER)
    // 4D matter: darker and glassier than scenery, no panels, an iridescent rim whose
    // hue turns with the view angle, and the w bands cut into it as light.
    float fres = (1.0 - ndv) * (1.0 - ndv);
    // Three phase-shifted triangle waves: a cosine palette's hues without three cosines.
    vec3 irid = abs(fract(vec3(0.0, 0.33, 0.67) + 1.3 * fres + v_fog_color.w) * 2.0 - 1.0);
    #ifdef FACETED
    vec4 planes = v_planes;
    #else
    vec4 planes = matter_coords(an, v_world);
    #endif
    float bands = w_bands(planes.xy);
    // A lattice of glowing diagonal lines: nothing in the scenery looks like it, and it
    // shows the surface's shape where the rim light cannot (faces seen head on).
    vec2 q = planes.zw;
    vec2 rfq = 1.0 / max(fwidth(q), vec2(1e-5));
    vec2 gq = (0.5 - abs(fract(q) - 0.5)) * rfq;
    float lattice = (1.0 - min(min(gq.x, gq.y) * (1.0 / 1.2), 1.0))
        * clamp(1.4 - 4.0 / min(rfq.x, rfq.y), 0.0, 1.0);
    albedo *= 0.6;
    gloss = 2.5;
    emit += albedo * 0.25 + fres * mix(HYPER_RIM, irid, 0.5) * 0.6;
    emit += lattice * v_sun.w * (v_color.rgb * 0.5 + 0.1);
    emit += bands * (0.35 * (v_band.z > 0.0 ? ANA : KATA) + 0.25 * albedo);
    albedo *= 1.0 - 0.45 * bands;
  #endif

  #if defined(STYLE_GHOST)
    // Ghosts are translucent films, often layered over the whole view: no specular, rim or
    // fill terms (a ghost is a hint of shape, and each term costs a full-screen pass's worth
    // of CPU on a software rasterizer), only the sun's direction and the view angle.
    vec3 lit = albedo * (0.2 + 0.35 * ndv + 0.6 * max(dot(N, v_sun.xyz), 0.0));
  #elif defined(STYLE_GLOW)
    // Emissive (crystals): lit from within, brightest at the silhouette, and
    // barely fogged, so it never reads as scenery under the same sun.
    vec3 lit = albedo * (0.75 + 1.6 * (1.0 - ndv) * (1.0 - ndv)) + vec3(0.06);
    #ifdef LOOK_SCIFI
    // A slow pulse, facets catching the light (x^24 by squaring), and the w bands as darker rings.
    lit *= v_sun.w;
    float r = max(dot(reflect(-V, N), v_sun.xyz), 0.0);
    float r2 = r * r;
    float r8 = r2 * r2;
    r8 *= r8;
    lit += vec3(0.5) * (r8 * r8 * r8);
    lit *= 1.0 - 0.5 * w_bands(matter_coords(an, v_world).xy);
    #endif
  #else
    vec3 L = v_sun.xyz;
    #if defined(FACETED)
    // The hemisphere ambient plus the sun's diffuse light, the same over the face.
    float diffuse = v_face_light.w;
    vec3 light = v_face_light.rgb;
    #elif defined(LOOK_SCIFI)
    float diffuse = max(dot(N, L), 0.0);
    vec3 light = AMBIENT + AMBIENT_UP * N.y + diffuse * KEY_LIGHT;
    #else
    float diffuse = max(dot(N, L), 0.0);
    // Hemisphere ambient: cool from above, dark from below, so faces facing
    // away from the light still show their orientation.
    vec3 ambient = mix(vec3(0.035, 0.035, 0.04), vec3(0.13, 0.15, 0.20), 0.5 + 0.5 * N.y);
    vec3 light = ambient + diffuse * vec3(1.0, 0.96, 0.90);
    #endif
    // Phong's highlight: R.V for the sun's reflection R = 2 (N.L) N - L, which is
    // 2 (N.L)(N.V) - L.V (where it counts, N.L >= 0). Blinn's N.H to the power 40 made the
    // same highlight as this power of 14 (all but 0.15 % of a frame's pixels within 4 of 255,
    // none more than 22 apart), but normalising H, one more inverse square root a pixel, was
    // a sixth of the floor's shading and 5-10 % of the walls' on llvmpipe.
    float rdv = 2.0 * diffuse * ndv - dot(L, V);
    float spec = diffuse > 0.0 ? pow_highlight(rdv, 14.0 * gloss) * 0.18 * gloss : 0.0;
    float rim = (1.0 - ndv) * (1.0 - ndv) * (1.0 - ndv) * 0.12;
    // A weak light from the eye keeps faces turned away from the sun readable.
    float fill = 0.22 * ndv;
    vec3 lit = albedo * (light + fill) + vec3(spec) + rim * vec3(0.55, 0.65, 0.9) + emit;
  #endif
#endif

#ifdef STYLE_GHOST
    // A little of the tint as light of its own: a ghost must read as "ana" or "kata"
    // even where the sun leaves its surface dark.
    lit += v_tint.rgb * v_tint.a * 0.3;
#endif
    vec3 color = to_display(lit);
    // Exponential-squared fog: 1 - exp(-(dist * density)^2), from the squared distance.
    float fog = 1.0 - exp_neg(dist2 * v_eye.w);
#ifdef STYLE_GLOW
    fog *= 0.4;
#endif
    // Atmospheric depth: distant things fade into the sky behind them (in the sci-fi look,
    // the dome's colour there; in the flat look, the one sky colour).
    color = mix(color, v_fog_color.rgb, fog);

#ifdef STYLE_GHOST
    // Slightly more opaque at grazing angles so a ghost's silhouette reads.
    float graze = (1.0 - ndv) * (1.0 - ndv);
    float alpha = v_sun.w * v_color.a * (1.0 + 0.6 * graze) * ghost_pattern(gl_FragCoord.xy);
    f_color = vec4(color, clamp(alpha, 0.0, 1.0));
#else
    f_color = vec4(color, 1.0);
#endif
}
""".replace("MATTER_COORDS", MATTER_COORDS)

#: Program names: the drawable styles, and ``hyper``, the solid style of 4D cross-sections
#: in the sci-fi look (the renderer picks it for drawables that carry a ``w_offset``).
PROGRAMS = ("solid", "floor", "wire", "ghost", "glow", "hyper")


#: The styles with a program for faceted meshes (see :func:`program_source`): the scenery's and
#: 4D matter's (batches of 4D things keep the general one: a flat input costs every triangle).
FACETED_STYLES = ("solid", "floor", "hyper")


def program_source(
    style: str, look: str = "flat", palette: Mapping | None = None, flat_normals: bool = False, faceted: bool = False
) -> tuple[str, str]:
    """Vertex and fragment source for a program of :data:`PROGRAMS` in a look (``scifi`` or ``flat``).

    ``hyper`` in the flat look is the solid program. In the sci-fi look the light colours of
    ``palette`` (default :data:`.materials.DEFAULT`; see :func:`palette_constants`) are
    compiled in; its sky colours stay uniforms. ``flat_normals``: the program for meshes whose
    normals are zero (frustum projections), which shades each face with its screen-space normal.
    ``faceted``: the program of a :data:`FACETED_STYLES` style in the sci-fi look for meshes whose
    every triangle has one normal (the level's boxes, sections of 4D worlds): the side facing the
    eye, the plane of the panels or w bands and the ambient and diffuse light are worked out per
    vertex (the same pixels, less work each).
    """
    if style == "hyper" and look != "scifi":
        style = "solid"
    header = f"#version 330\n#define STYLE_{style.upper()}\n"
    if flat_normals:
        header += "#define FLAT_NORMALS\n"
    elif faceted and look == "scifi" and style in FACETED_STYLES:
        header += "#define FACETED\n"
    if look == "scifi":
        header += "#define LOOK_SCIFI\n"
        header += "".join(f"#define {name} {value}\n" for name, value in palette_constants(palette))
    return header + VERTEX, header + FRAGMENT


def palette_constants(palette: Mapping | None = None) -> tuple[tuple[str, str], ...]:
    """The sci-fi fragment shader's colour constants from ``palette``: ``(name, GLSL vec3)`` pairs.

    The key light, the hemisphere ambient (at a vertical face, and what facing up adds), the
    trims, the floor's lines, ana and kata and the rim of 4D matter, all linear RGB.
    """
    c = materials.DEFAULT if palette is None else palette

    def vec3(rgb) -> str:
        return "vec3({:.7g}, {:.7g}, {:.7g})".format(*(float(x) for x in rgb))

    sky, ground = c["ambient_sky"], c["ambient_ground"]
    return (
        ("KEY_LIGHT", vec3(c["key_light"])),
        ("AMBIENT", vec3(0.5 * (float(s) + float(g)) for s, g in zip(sky, ground))),
        ("AMBIENT_UP", vec3(0.5 * (float(s) - float(g)) for s, g in zip(sky, ground))),
        ("TRIM", vec3(c["trim"])),
        ("FLOOR_LINE", vec3(c["floor_line"])),
        ("ANA", vec3(c["ana"])),
        ("KATA", vec3(c["kata"])),
        ("HYPER_RIM", vec3(c["hyper_rim"])),
    )


#: Unlit lines and triangles in one colour per vertex (the radar's disc and pins' stems, the
#: physics debug overlay): positions already in world space, no lighting, no fog.
FLAT_VERTEX = """
#version 330
uniform mat4 u_view_proj;
in vec3 in_pos;
in vec4 in_color;
out vec4 v_color;
void main() {
    v_color = in_color;
    gl_Position = u_view_proj * vec4(in_pos, 1.0);
}
"""

FLAT_FRAGMENT = """
#version 330
in vec4 v_color;
out vec4 f_color;
void main() {
    f_color = v_color;
}
"""
