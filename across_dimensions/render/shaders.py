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

void main() {
    vec4 world = u_model * vec4(in_pos, 1.0);
    v_world = world.xyz;
    v_normal = u_normal_mat * in_normal;
    v_color = in_color;
    gl_Position = u_view_proj * world;
#ifdef STYLE_WIRE
    // Pull lines slightly toward the camera so an outline drawn over a solid
    // with the same geometry wins the depth test instead of z-fighting.
    gl_Position.z -= 2e-4 * gl_Position.w;
#endif
}
"""

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

in vec3 v_world;
in vec3 v_normal;
in vec4 v_color;

out vec4 f_color;

vec3 to_display(vec3 c) {
    // Linear up to 0.8, then a soft shoulder approaching 1.0.
    c = max(c, 0.0);
    vec3 over = max(c - 0.8, 0.0);
    c = min(c, 0.8) + 0.2 * (1.0 - exp(-over / 0.2));
    return sqrt(c);
}

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

  #ifdef STYLE_FLOOR
    // Grid on the plane most facing the normal: world xz for floors.
    vec3 an = abs(N);
    vec2 uv = an.y >= max(an.x, an.z) ? v_world.xz : (an.x >= an.z ? v_world.zy : v_world.xy);
    float minor = grid_lines(uv, 1.0);
    float major = grid_lines(uv, 10.0);
    albedo = mix(albedo, albedo * 0.35 + vec3(0.10, 0.16, 0.22), max(minor * 0.55, major));
  #endif

  #ifdef STYLE_GLOW
    // Emissive (crystals): lit from within, brightest at the silhouette, and
    // barely fogged, so it never reads as scenery under the same sun.
    vec3 lit = albedo * (0.75 + 1.6 * pow(1.0 - ndv, 2.0)) + vec3(0.06);
  #else
    vec3 L = u_light_dir;
    float diffuse = max(dot(N, L), 0.0);
    // Hemisphere ambient: cool from above, dark from below, so faces facing
    // away from the light still show their orientation.
    vec3 ambient = mix(vec3(0.035, 0.035, 0.04), vec3(0.13, 0.15, 0.20), 0.5 + 0.5 * N.y);
    vec3 H = normalize(L + V);
    float spec = diffuse > 0.0 ? pow(max(dot(N, H), 0.0), 40.0) * 0.18 : 0.0;
    float rim = pow(1.0 - ndv, 3.0) * 0.12;
    // A weak light from the eye keeps faces turned away from the sun readable.
    float fill = 0.22 * ndv;
    vec3 lit = albedo * (ambient + fill + diffuse * vec3(1.0, 0.96, 0.90)) + vec3(spec) + rim * vec3(0.55, 0.65, 0.9);
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
    color = mix(color, u_sky, fog);

#ifdef STYLE_GHOST
    // Slightly more opaque at grazing angles so a ghost's silhouette reads.
    float alpha = u_alpha * u_opacity * v_color.a * (1.0 + 0.6 * pow(1.0 - ndv, 2.0)) * ghost_pattern(gl_FragCoord.xy);
    f_color = vec4(color, clamp(alpha, 0.0, 1.0));
#else
    f_color = vec4(color, 1.0);
#endif
}
"""


def program_source(style: str) -> tuple[str, str]:
    """Vertex and fragment source for a style (``solid``, ``ghost``, ``wire``, ``floor``, ``glow``)."""
    header = f"#version 330\n#define STYLE_{style.upper()}\n"
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
