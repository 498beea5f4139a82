#pragma once
/// GLSL 3.30 core sources of the renderer (docs/render.md: the look of tissue under a scope).
namespace trocar::shaders {

/// Meshes: world position, normal and a texture coordinate (the rest position, so the procedural
/// texture stays on the tissue as it deforms). With TROCAR_EFFECTS (kEffectsDefine), also what
/// electrosurgery and bleeding did to each vertex (location 3: coagulation, charring, blood film,
/// stain; docs/electrosurgery.md "What is drawn").
inline constexpr const char* kMeshVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_texcoord;
#ifdef TROCAR_EFFECTS
layout(location = 3) in vec4 a_effects;
out vec4 v_effects;
#endif
#ifdef TROCAR_SMOKE
uniform sampler2D u_smoke_field;  // the smoke's low-resolution field (below, "Smoke")
uniform vec2 u_smoke_scale;       // its texture coordinates per frame pixel
uniform vec2 u_viewport;
uniform vec3 u_eye;
out vec2 v_smoke;                 // the smoke in front of this vertex: alpha, light
#endif
uniform mat4 u_model;
uniform mat4 u_view_projection;
uniform mat3 u_normal_matrix;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_texcoord;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_texcoord = a_texcoord;
#ifdef TROCAR_EFFECTS
  v_effects = a_effects;
#endif
  gl_Position = u_view_projection * world;
#ifdef TROCAR_SMOKE
  // Sampled per vertex (under llvmpipe a texture read per pixel costs as much as the rest of the
  // smoke): the field where the vertex lands, the share of its optical depth nearer than it.
  vec2 pixel = (gl_Position.xy / max(gl_Position.w, 1e-6) * 0.5 + 0.5) * u_viewport;
  vec4 smoke = textureLod(u_smoke_field, pixel * u_smoke_scale, 0.0);
  float in_front = clamp(0.5 + (distance(world.xyz, u_eye) - smoke.z) * smoke.w, 0.0, 1.0);
  v_smoke = gl_Position.w > 0.0 ? vec2(1.0 - exp2(-smoke.x * in_front), smoke.y) : vec2(0.0);
#endif
}
)";

/// Modes: 0 tissue (solid noise texture with vessels, wet specular), 1 metal, 2 flat colour (the
/// id pass of the tests), 3 textured tissue with the mesh's own UVs in v_texcoord.xy.
/// Light: a headlight at the eye (the scope's fibre light), falling off with distance.
/// Compiled twice: as it is for the default look, and with TROCAR_LOOKS defined (kLooksDefine)
/// for objects with an appearance — mode 4 plain (u_base under the same light as tissue), mode 5
/// an open knitted weave (the prosthetic mesh) on the plane coordinates in v_texcoord.xy (m),
/// holes discarded, and u_opacity as the fragment's alpha. The default program's code is thereby
/// the same as before appearances existed, so default frames stay identical bit for bit (a larger
/// shader compiles to slightly different arithmetic under llvmpipe). A third variant, with both
/// TROCAR_LOOKS and TROCAR_EFFECTS (kEffectsDefine), draws only the tissues that something burnt
/// or bled on: in the tissue branch (modes 0, 3, 4) coagulation turns the albedo white-tan and
/// dulls the wet highlight, charring turns it brown then black, the blood film is wet dark red
/// with a stronger highlight, and its stain a darker red-brown where the film has gone.
inline constexpr const char* kMeshFragment = R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec3 v_texcoord;
#ifdef TROCAR_EFFECTS
in vec4 v_effects;
#endif
out vec4 o_color;
uniform int u_mode;
uniform vec3 u_eye;
uniform vec3 u_base;
uniform vec3 u_vessel;
uniform float u_vessel_strength;  // 0..1: how much the vessel colour covers the albedo
uniform float u_texture_scale;   // noise cells per metre
uniform float u_light_range;     // m: distance at which the light has fallen to one half
uniform float u_vignette;        // 0 = none; else the radius (in half-heights) where darkening starts
uniform vec2 u_viewport;
uniform sampler2D u_texture;
#ifdef TROCAR_SMOKE
in vec2 v_smoke;                  // the smoke in front of the surface: alpha, light (kMeshVertex)
uniform vec3 u_smoke_colour;      // linear albedo
#endif
#ifdef TROCAR_LOOKS
uniform float u_opacity;          // alpha of the fragment (blended when < 1)
uniform float u_weave_period;     // m: the weave's repeat
#endif

float hash(vec3 p) {
  p = fract(p * 0.3183099 + vec3(0.71, 0.113, 0.419));
  p *= 17.0;
  return fract(p.x * p.y * p.z * (p.x + p.y + p.z));
}
float value_noise(vec3 x) {
  vec3 i = floor(x);
  vec3 f = fract(x);
  f = f * f * (3.0 - 2.0 * f);
  return mix(mix(mix(hash(i + vec3(0, 0, 0)), hash(i + vec3(1, 0, 0)), f.x),
                 mix(hash(i + vec3(0, 1, 0)), hash(i + vec3(1, 1, 0)), f.x), f.y),
             mix(mix(hash(i + vec3(0, 0, 1)), hash(i + vec3(1, 0, 1)), f.x),
                 mix(hash(i + vec3(0, 1, 1)), hash(i + vec3(1, 1, 1)), f.x), f.y), f.z);
}
float fbm(vec3 p) {
  float sum = 0.0, amplitude = 0.5;
  for (int k = 0; k < 4; ++k) { sum += amplitude * value_noise(p); p = p * 2.03 + vec3(1.7); amplitude *= 0.5; }
  return sum;
}
// Vessels: the zero set of a noise field is a web of thin branching lines (ridged noise).
float vessels(vec3 p) {
  float r1 = 1.0 - abs(2.0 * fbm(p) - 1.0);
  float r2 = 1.0 - abs(2.0 * fbm(p * 2.7 + vec3(5.2)) - 1.0);
  return max(smoothstep(0.972, 0.993, r1), 0.6 * smoothstep(0.978, 0.996, r2));
}

#ifdef TROCAR_LOOKS
// A warp-knitted net: two families of filaments along the diagonals of the period cell, each
// wavy where it loops round the other. Returns (coverage 0..1, the filament's roundness 0..1 for
// shading); coverage is antialiased over the pixel's footprint and tends to its mean when the
// net is finer than a few pixels (no moire).
vec2 weave(vec2 q) {
  float a = q.x + q.y, b = q.x - q.y;
  float da = abs(fract(a + 0.07 * sin(6.2831853 * b)) - 0.5);
  float db = abs(fract(b + 0.07 * sin(6.2831853 * a)) - 0.5);
  const float w = 0.15;  // half-width of a filament, in periods of a (holes ~ (1 - 2w)^2 of the area)
  float aa = 0.75 * max(fwidth(a), fwidth(b));
  float ca = 1.0 - smoothstep(w - aa, w + aa, da);
  float cb = 1.0 - smoothstep(w - aa, w + aa, db);
  float coverage = max(ca, cb);
  float round_a = sqrt(max(0.0, 1.0 - (da / w) * (da / w)));
  float round_b = sqrt(max(0.0, 1.0 - (db / w) * (db / w)));
  float roundness = max(round_a, round_b);
  float fine = smoothstep(0.12, 0.35, aa);
  return vec2(mix(coverage, 0.6, fine), mix(roundness, 0.7, fine));
}
#endif

void main() {
  if (u_mode == 2) { o_color = vec4(u_base, 1.0); return; }
#ifdef TROCAR_LOOKS
  vec2 filament = vec2(1.0);
  if (u_mode == 5) {
    filament = weave(v_texcoord.xy / u_weave_period);
    if (filament.x < 0.5) discard;  // a hole: what lies behind shows through
  }
#endif
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;   // open sheets (peritoneum) are lit from both sides
  vec3 to_eye = u_eye - v_world;
  float d = length(to_eye);
  vec3 l = to_eye / max(d, 1e-6);
  float ndl = max(dot(n, l), 0.0);
  float falloff = 1.0 / (1.0 + (d * d) / (u_light_range * u_light_range));
  vec3 color;
  if (u_mode == 1) {
    // Brushed steel: low diffuse, a broad and a sharp lobe, brighter at grazing angles.
    float fresnel = pow(1.0 - ndl, 4.0);
    vec3 diffuse = u_base * (0.25 + 0.45 * ndl);
    float spec = 0.9 * pow(ndl, 40.0) + 0.35 * pow(ndl, 6.0);
    color = (diffuse + vec3(spec) + 0.25 * fresnel * vec3(0.8, 0.85, 0.9)) * falloff;
  }
#ifdef TROCAR_LOOKS
  else if (u_mode == 5) {
    // Polypropylene filament: a round thread lit by the headlight, a tight glossy highlight.
    float shade = 0.55 + 0.45 * filament.y;
    float spec = 0.5 * pow(ndl, 30.0) * filament.y;
    color = (u_base * shade * (0.15 + 0.85 * ndl) + vec3(spec)) * falloff;
  }
#endif
  else {
    vec3 albedo;
#ifdef TROCAR_EFFECTS
    float grain = 0.5;  // mottles burns and stains: the tissue's own mottling (an image's: none)
#endif
#ifdef TROCAR_LOOKS
    if (u_mode == 4) albedo = u_base; else
#endif
    if (u_mode == 3) {
      albedo = texture(u_texture, v_texcoord.xy).rgb;
    } else {
      vec3 p = v_texcoord * u_texture_scale;
      float mottling = fbm(p * 0.8);
#ifdef TROCAR_EFFECTS
      grain = mottling;
#endif
      albedo = u_base * (0.75 + 0.5 * mottling);
      albedo = mix(albedo, vec3(0.86, 0.70, 0.52), 0.35 * smoothstep(0.62, 0.78, fbm(p * 0.35 + vec3(9.1))));
      albedo = mix(albedo, u_vessel, u_vessel_strength * vessels(p * 0.5));
    }
    // Wet tissue under a headlight: Lambert plus a tight, strong highlight (mucosal film) and
    // a weak broad one; light and eye coincide, so the half vector is l.
    float spec = 0.85 * pow(ndl, 80.0) + 0.12 * pow(ndl, 10.0);
#ifdef TROCAR_EFFECTS
    // What electrosurgery and bleeding did here (4 values per vertex, interpolated).
    vec4 e = clamp(v_effects, 0.0, 1.0);
    // Coagulated: denatured protein, white-tan and mottled, drier (the mucosal film is gone: a
    // dull sheen); where it is partly coagulated (the rim), cooked blood browns it.
    float rim = smoothstep(0.05, 0.45, e.x) * (1.0 - smoothstep(0.45, 0.9, e.x));
    albedo = mix(albedo, vec3(0.50, 0.27, 0.20), 0.55 * rim);
    float coagulated = smoothstep(0.3, 0.9, e.x);
    albedo = mix(albedo, vec3(0.80, 0.72, 0.58) * (0.8 + 0.4 * grain), coagulated);
    spec *= 1.0 - 0.75 * coagulated;
    // Charring: brown where the water has boiled off, black where it is carbonised (a cut's edges).
    float charred = smoothstep(0.05, 0.6, e.y) * (0.75 + 0.25 * grain);
    vec3 char_colour = mix(vec3(0.30, 0.12, 0.04), vec3(0.03, 0.02, 0.015), smoothstep(0.4, 0.9, e.y));
    albedo = mix(albedo, char_colour, charred);
    spec *= 1.0 - 0.85 * charred;
    // Stain: a darker red-brown where blood has passed and gone; the wet film over it: dark red,
    // with the tight highlight of a liquid surface.
    albedo = mix(albedo, vec3(0.20, 0.025, 0.015) * (0.8 + 0.4 * grain), e.w);
    float wet = smoothstep(0.06, 0.3, e.z);  // above the residual layer (20 µm = 0.04): a flowing film
    albedo = mix(albedo, vec3(0.30, 0.015, 0.01), wet);
    // A liquid's highlight: tighter and stronger than the mucosa's, no broad sheen.
    float n4 = (ndl * ndl) * (ndl * ndl), n16 = (n4 * n4) * (n4 * n4), n64 = (n16 * n16) * (n16 * n16);
    spec = mix(spec, 1.2 * n64 * n16 + 0.03 * n16, wet);
#endif
    color = (albedo * (0.06 + 0.94 * ndl) + vec3(spec)) * falloff;
  }
#ifdef TROCAR_SMOKE
  color = mix(color, u_smoke_colour * v_smoke.y, v_smoke.x);  // the smoke in front of it
#endif
  if (u_vignette > 0.0) {
    vec2 c = (gl_FragCoord.xy - 0.5 * u_viewport) / (0.5 * u_viewport.y);
    color *= 1.0 - smoothstep(u_vignette, u_vignette + 0.6, length(c));
  }
#ifdef TROCAR_LOOKS
  o_color = vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), u_opacity);
#else
  o_color = vec4(pow(clamp(color, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0);
#endif
}
)";

/// Put after kMeshFragment's first line: its appearance variant.
inline constexpr const char* kLooksDefine = "#define TROCAR_LOOKS\n";
/// Put after the first line of kMeshVertex and kMeshFragment (with kLooksDefine): the variant
/// for tissues with burns or blood.
inline constexpr const char* kEffectsDefine = "#define TROCAR_EFFECTS\n";

/// Put after kMeshFragment's first line (with kLooksDefine and kEffectsDefine as needed): the
/// variants that draw every object of a frame with smoke on screen (below).
inline constexpr const char* kSmokeDefine = "#define TROCAR_SMOKE\n";

/// Smoke (docs/electrosurgery.md "What is drawn"). Each puff is a soft round disc facing the
/// camera: its alpha the puff's opacity at the centre falling off as (1 − ρ²)² (ρ: the distance
/// from the centre over the radius; Gaussian-like, zero at the rim). The renderer adds the puffs
/// up, in any order, into a low-resolution field per pixel: the optical depth τ = Σ −ln(1 − alpha)
/// (e^−τ is what alpha blending of the puffs, all of one colour, would let through), and its
/// τ-weighted light (the headlight's falloff at each puff, as for the tissue), distance from the
/// eye and spread of distances. Each surface then takes the share of τ in front of it (the
/// distances taken as uniform over mean ± √3 σ): a soft depth test, so smoke behind an
/// instrument does not veil it; per vertex, interpolated over its triangles (kMeshVertex).
/// Grey-white: smoke near the scope is bright and veils the view.
/// The field's texel: (τ log2 e, light, mean distance (m), 1 / (2√3 σ) (1/m)).
/// The smoke over the cavity's darkness where no surface was drawn (a quad on the far plane):
/// its colour per field texel, as drawn (the renderer computes it: the clear colour veiled by
/// the smoke, vignetted, gamma-encoded).
inline constexpr const char* kSmokeBackdropVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
void main() { gl_Position = vec4(a_position, 1.0); }
)";

inline constexpr const char* kSmokeBackdropFragment = R"(#version 330 core
out vec4 o_color;
uniform sampler2D u_backdrop;
uniform vec2 u_scale;  // texture coordinates per frame pixel
void main() { o_color = texture(u_backdrop, gl_FragCoord.xy * u_scale); }
)";

/// Overlays: lines, points and screen-space quads in one colour.
inline constexpr const char* kOverlayVertex = R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_matrix;
uniform float u_point_size;
void main() {
  gl_Position = u_matrix * vec4(a_position, 1.0);
  gl_PointSize = u_point_size;
}
)";

inline constexpr const char* kOverlayFragment = R"(#version 330 core
out vec4 o_color;
uniform vec4 u_color;
void main() { o_color = u_color; }
)";

}  // namespace trocar::shaders
