"""GLSL sources for the scene renderer.

One vertex/fragment pair, specialised per drawable style with ``#define``s, so
each compiled program carries only the code its style needs (llvmpipe runs
fragment shaders on the CPU: every instruction counts at 1280x720).

Colour pipeline: vertex colours are linear RGB; lighting happens in linear
space; the result goes through a soft shoulder (so highlights don't clip
harshly) and a gamma of 2 (``sqrt``: close to sRGB's ~2.2 and cheaper than
``pow`` when llvmpipe runs the shader on the CPU); fog then mixes toward the
sky colour, which is a *display* colour (the framebuffer is cleared with it
unchanged), so distant surfaces fade exactly into the sky.
"""

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

VERTEX = """
uniform mat4 u_view_proj;
uniform mat4 u_model;
uniform mat3 u_normal_mat;

in vec3 in_pos;
in vec3 in_normal;
in vec4 in_color;

out vec3 v_world;
out vec3 v_normal;
out vec4 v_color;
#ifdef LOOK_SCIFI
uniform vec3 u_eye;
uniform vec3 u_sky_zenith;
uniform vec3 u_sky_horizon;
uniform vec3 u_sky_ground;
out vec3 v_fog_color;  // the sky behind the vertex: smooth, so per vertex is enough
SKY_GRADIENT
#endif

void main() {
    vec4 world = u_model * vec4(in_pos, 1.0);
    v_world = world.xyz;
#ifdef LOOK_SCIFI
    v_fog_color = sky_gradient(normalize(world.xyz - u_eye));
#endif
    v_normal = u_normal_mat * in_normal;
    v_color = in_color;
    gl_Position = u_view_proj * world;
#ifdef STYLE_WIRE
    // Pull lines slightly toward the camera so an outline drawn over a solid
    // with the same geometry wins the depth test instead of z-fighting.
    gl_Position.z -= 2e-4 * gl_Position.w;
#endif
}
""".replace("SKY_GRADIENT", SKY_GRADIENT)

FRAGMENT = """
uniform vec3 u_eye;
uniform vec3 u_light_dir;   // toward the light, normalised on the CPU
uniform vec3 u_sky;         // display-space sky colour (fog target)
uniform float u_fog_density;
uniform float u_alpha;      // ghost opacity
#ifdef STYLE_GHOST
uniform vec4 u_tint;        // rgb the ghost's colour is pulled to, and how far (a)
uniform int u_pattern;      // 0 plain, 1 stripes, 2 dots (screen space)
uniform float u_opacity;    // per-drawable factor (fading along w, preview emphasis)
#endif
#ifdef LOOK_SCIFI
uniform float u_time;       // seconds, for slow animation (bands drift)
uniform float u_pulse;      // the trims' slow breathing, 0.8 to 1 (set once a frame)
uniform vec3 u_sky_zenith;  // display colours of the sky dome (fog goes to its horizon)
uniform vec3 u_sky_horizon;
uniform vec3 u_sky_ground;
uniform vec3 u_key_light;   // linear light colours
uniform vec3 u_ambient_sky;
uniform vec3 u_ambient_ground;
uniform vec3 u_trim;
uniform vec3 u_floor_line;
uniform vec3 u_ana;
uniform vec3 u_kata;
uniform vec3 u_hyper_rim;
uniform float u_w_offset;   // 4D things: (w of the thing - w of the slice) / its half extent in w
uniform float u_band_scale; // metres per band unit (the drawable's size)
uniform float u_w_from_alpha; // 1: each vertex's colour alpha is its thing's w offset (batches)
#endif

in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;
#ifdef LOOK_SCIFI
in vec3 v_fog_color;
#endif

out vec4 f_color;

vec3 to_display(vec3 c) {
    // Linear up to 0.8, then a soft shoulder approaching 1.0.
    c = max(c, 0.0);
    vec3 over = max(c - 0.8, 0.0);
    // (A rational shoulder: the same slope and limit as 0.2 * (1 - exp(-over / 0.2)), no exp.)
    c = min(c, 0.8) + over / (1.0 + 5.0 * over);
    return sqrt(c);
}

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
// The w cue of 4D matter, in pattern and motion rather than colour: bands across the
// surface whose spacing shrinks as the slice nears the edge of the thing along w (sparse
// and faint at its centre, dense at the edge), solid lines rising when the thing lies ana
// (+w) of the slice and dotted lines sinking when it lies kata (-w), the same sides as
// the ghosts' stripes and dots. Returns the band mask in 0-1.
float w_offset_here() {
    return u_w_from_alpha > 0.5 ? v_color.a : u_w_offset;
}

float w_bands(vec3 N) {
    float w_off = w_offset_here();
    float a = min(abs(w_off), 1.0);
    float side = w_off >= 0.0 ? 1.0 : -1.0;
    float period = u_band_scale * mix(0.9, 0.14, a);
    vec3 an = abs(N);
    // Across vertical faces the bands are levels of height; on horizontal faces, diagonals.
    float s = an.y > 0.7 ? (v_world.x + v_world.z) * 0.7071 : v_world.y;
    float t = s / period - side * u_time * (0.25 + 0.9 * a);
    float fw = max(fwidth(t), 1e-5);
    float d = abs(fract(t) - 0.5);  // 0.5 at a band's middle
    float band = smoothstep(0.5 - 0.16 - fw, 0.5 - 0.16 + fw, d);
    if (side < 0.0) {
        // kata: dotted, the dots as long as the bands are wide
        float u = (an.x > an.z ? v_world.z : v_world.x) / period;
        float fu = max(fwidth(u), 1e-5);
        band *= smoothstep(0.25 - fu, 0.25 + fu, abs(fract(u) - 0.5));
    }
    // No bands right at the centre (nothing to warn about), and none where they would alias.
    return band * smoothstep(0.06, 0.22, a) * (1.0 - smoothstep(0.25, 0.5, fw));
}
#endif

#ifdef STYLE_GHOST
// Screen-space patterns, so the two sides of the slice differ in texture as well as
// hue (never colour alone) at any distance and on any surface. 1 on the pattern's
// marks, a faint floor between them so the ghost's shape still reads.
float ghost_pattern(vec2 px) {
    if (u_pattern == 1) {
        // Diagonal stripes, 9 px period, 4 px wide, anti-aliased by fwidth.
        float t = (px.x + px.y) / 9.0;
        float d = abs(fract(t) - 0.5) * 9.0;
        return 0.35 + 0.65 * (1.0 - smoothstep(1.5, 2.5, d));
    }
    if (u_pattern == 2) {
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
    albedo = mix(albedo, u_tint.rgb, u_tint.a);
#endif
    vec3 to_eye = u_eye - v_world;
    float dist = length(to_eye);
    vec3 V = to_eye / max(dist, 1e-6);
    vec3 emit = vec3(0.0);  // light of the surface's own, added after lighting

#ifdef STYLE_WIRE
    vec3 lit = albedo;
#else
    float nlen = length(v_normal);
    // Meshes without normals (frustum projections) are shaded flat, with the
    // face normal taken from screen-space derivatives of the position.
    vec3 N = nlen > 1e-8 ? v_normal / nlen : normalize(cross(dFdx(v_world), dFdy(v_world)));
    // Two-sided lighting: no culling and a mirrored view matrix mean we may see
    // either side of a triangle, so light the side facing the eye.
    float ndv = dot(N, V);
    if (ndv < 0.0) { N = -N; ndv = -ndv; }
    vec3 an = abs(N);
    float gloss = 1.0;

  #if defined(LOOK_SCIFI) && (defined(STYLE_SOLID) || defined(STYLE_FLOOR))
    // Scenery is plated: panels on the world plane the surface faces (1.5 x 1 m on
    // walls, 2 m on floors), each a little lighter or darker, with dark seams, and a
    // few vented panels. Cheap (no textures, no branches on the common path, linear
    // anti-aliasing instead of smoothstep) and stable in world space.
    bool flat_face = an.y >= max(an.x, an.z);
    float wall = flat_face ? 0.0 : 1.0;
    vec2 size = flat_face ? vec2(2.0) : vec2(1.5, 1.0);
    vec2 p = (flat_face ? v_world.xz : (an.x >= an.z ? v_world.zy : v_world.xy)) / size;
    vec2 cell = floor(p);
    vec2 fw = max(fwidth(p), vec2(1e-5));
    // Pixels to the nearest seam on each axis; seams ~1.5 px wide, fading out where panels
    // shrink below ~10 px (distance, grazing angles) instead of aliasing into moire.
    vec2 g = (0.5 - abs(fract(p) - 0.5)) / fw;
    float fade = clamp(4.0 - 13.0 * max(fw.x, fw.y), 0.0, 1.0);
    vec2 seams = clamp(1.5 - g, 0.0, 1.0) * fade;
    float h = hash12(cell + floor(v_world.y * 0.25) * 17.0);
    // Cool, darker steel than the level's colours say: the emissive trims and the 4D
    // matter are the brightest things in view, so the eye goes to them.
    albedo *= vec3(0.70, 0.74, 0.82) * ((0.84 + 0.3 * h) * (1.0 - 0.6 * max(seams.x, seams.y)));
    gloss = 0.5 + h;
    if (h > 0.95 && wall > 0.5) {
        // A vent: horizontal slats over the panel's middle.
        vec2 f = fract(p);
        float inside = step(0.2, f.x) * step(f.x, 0.8) * step(0.3, f.y) * step(f.y, 0.7);
        float slat = clamp((abs(fract(p.y * 16.0) - 0.5) - 0.25) / (16.0 * fw.y) + 0.5, 0.0, 1.0);
        albedo *= 1.0 - 0.55 * inside * slat;
    }
    #ifdef STYLE_FLOOR
    // Lit lines every 10 m (every fifth seam): wayfinding at a glance, and scale.
    vec2 major = step(mod(floor(p + 0.5), 5.0), vec2(0.5)) * seams;
    emit += u_floor_line * (0.9 * max(major.x, major.y));
    #else
    // An emissive trim a hand above the floor (y 0.10 to 0.16), breathing slowly, over a
    // dark kick plate; walls darken upward, away from the trim and the floor's bounce.
    float y = v_world.y;
    float fy = max(fwidth(y), 1e-4);
    float trim = clamp((y - 0.10) / fy + 0.5, 0.0, 1.0) * clamp((0.16 - y) / fy + 0.5, 0.0, 1.0);
    float kick = clamp((0.10 - y) / fy + 0.5, 0.0, 1.0);
    albedo *= 1.0 - wall * (0.5 * kick + 0.35 * clamp((y - 0.3) / 3.7, 0.0, 1.0));
    emit += u_trim * (wall * trim * u_pulse);
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
    vec3 irid = abs(fract(vec3(0.0, 0.33, 0.67) + 1.3 * fres + 0.05 * u_time) * 2.0 - 1.0);
    vec3 side_tint = w_offset_here() >= 0.0 ? u_ana : u_kata;
    float bands = w_bands(N);
    // A lattice of glowing diagonal lines: nothing in the scenery looks like it, and it
    // shows the surface's shape where the rim light cannot (faces seen head on).
    vec2 huv = an.y > 0.7 ? v_world.xz : (an.x > an.z ? v_world.zy : v_world.xy);
    vec2 q = vec2(huv.x + huv.y, huv.x - huv.y) * 2.0;
    vec2 fq = max(fwidth(q), vec2(1e-5));
    vec2 gq = (0.5 - abs(fract(q) - 0.5)) / fq;
    float lattice = (1.0 - min(min(gq.x, gq.y) / 1.2, 1.0)) * (1.0 - smoothstep(0.1, 0.35, max(fq.x, fq.y)));
    albedo *= 0.6;
    gloss = 2.5;
    emit += albedo * 0.25 + fres * mix(u_hyper_rim, irid, 0.5) * 0.6;
    emit += lattice * u_pulse * (v_color.rgb * 0.5 + 0.1);
    emit += bands * (0.35 * side_tint + 0.25 * albedo);
    albedo *= 1.0 - 0.45 * bands;
  #endif

  #if defined(STYLE_GHOST)
    // Ghosts are translucent films, often layered over the whole view: no specular, rim or
    // fill terms (a ghost is a hint of shape, and each term costs a full-screen pass's worth
    // of CPU on a software rasterizer), only the sun's direction and the view angle.
    vec3 lit = albedo * (0.2 + 0.35 * ndv + 0.6 * max(dot(N, u_light_dir), 0.0));
  #elif defined(STYLE_GLOW)
    // Emissive (crystals): lit from within, brightest at the silhouette, and
    // barely fogged, so it never reads as scenery under the same sun.
    vec3 lit = albedo * (0.75 + 1.6 * (1.0 - ndv) * (1.0 - ndv)) + vec3(0.06);
    #ifdef LOOK_SCIFI
    // A slow pulse, facets catching the light, and the w bands as darker rings.
    lit *= 0.9 + 0.15 * sin(u_time * 2.4);
    lit += vec3(0.5) * pow(max(dot(reflect(-V, N), u_light_dir), 0.0), 24.0);
    lit *= 1.0 - 0.5 * w_bands(N);
    #endif
  #else
    vec3 L = u_light_dir;
    float diffuse = max(dot(N, L), 0.0);
    #ifdef LOOK_SCIFI
    vec3 key = u_key_light;
    vec3 ambient = mix(u_ambient_ground, u_ambient_sky, 0.5 + 0.5 * N.y);
    #else
    vec3 key = vec3(1.0, 0.96, 0.90);
    // Hemisphere ambient: cool from above, dark from below, so faces facing
    // away from the light still show their orientation.
    vec3 ambient = mix(vec3(0.035, 0.035, 0.04), vec3(0.13, 0.15, 0.20), 0.5 + 0.5 * N.y);
    #endif
    vec3 H = normalize(L + V);
    float spec = diffuse > 0.0 ? pow(max(dot(N, H), 0.0), 40.0 * gloss) * 0.18 * gloss : 0.0;
    float rim = (1.0 - ndv) * (1.0 - ndv) * (1.0 - ndv) * 0.12;
    // A weak light from the eye keeps faces turned away from the sun readable.
    float fill = 0.22 * ndv;
    vec3 lit = albedo * (ambient + fill + diffuse * key) + vec3(spec) + rim * vec3(0.55, 0.65, 0.9) + emit;
  #endif
#endif

#ifdef STYLE_GHOST
    // A little of the tint as light of its own: a ghost must read as "ana" or "kata"
    // even where the sun leaves its surface dark.
    lit += u_tint.rgb * u_tint.a * 0.3;
#endif
    vec3 color = to_display(lit);
    float fd = dist * u_fog_density;
    float fog = 1.0 - exp(-fd * fd);
#ifdef STYLE_GLOW
    fog *= 0.4;
#endif
#ifdef LOOK_SCIFI
    // Atmospheric depth: distant things fade into the sky behind them, not into one colour.
    color = mix(color, v_fog_color, fog);
#else
    color = mix(color, u_sky, fog);
#endif

#ifdef STYLE_GHOST
    // Slightly more opaque at grazing angles so a ghost's silhouette reads.
    float graze = (1.0 - ndv) * (1.0 - ndv);
    float alpha = u_alpha * u_opacity * v_color.a * (1.0 + 0.6 * graze) * ghost_pattern(gl_FragCoord.xy);
    f_color = vec4(color, clamp(alpha, 0.0, 1.0));
#else
    f_color = vec4(color, 1.0);
#endif
}
"""

#: Program names: the drawable styles, and ``hyper``, the solid style of 4D cross-sections
#: in the sci-fi look (the renderer picks it for drawables that carry a ``w_offset``).
PROGRAMS = ("solid", "floor", "wire", "ghost", "glow", "hyper")


def program_source(style: str, look: str = "flat") -> tuple[str, str]:
    """Vertex and fragment source for a program of :data:`PROGRAMS` in a look (``scifi`` or ``flat``).

    ``hyper`` in the flat look is the solid program.
    """
    if style == "hyper" and look != "scifi":
        style = "solid"
    header = f"#version 330\n#define STYLE_{style.upper()}\n"
    if look == "scifi":
        header += "#define LOOK_SCIFI\n"
    return header + VERTEX, header + FRAGMENT


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
