// Forward Blinn-Phong scene shader: one directional light, ambient + diffuse + specular,
// base-colour texture with mip bias, alpha-mask materials (alpha test, or sharpened
// alpha-to-coverage), and screen-space motion vectors in a second target.
//
// Three vertex/fragment entry-point pairs differ only in how varyings are interpolated:
//   *_center   : at the pixel centre (ordinary MSAA: one shade per pixel)
//   *_centroid : texture coordinates at the centroid of the covered samples
//   *_sample   : every varying per sample, which makes the fragment shader run once per sample
//                (sample-rate shading: MSAA turned into SSAA at the same count)
// WebGPU requires the interpolation of a vertex output to match the fragment input, hence the
// pairs; all of them share `shade_vertex` and `shade_fragment`.

struct View {
    // Rasterisation matrix: projection with the sub-pixel jitter (and SSAA tile) applied.
    view_proj: mat4x4<f32>,
    // Un-jittered matrices of this and the previous frame, for motion vectors.
    unjittered_view_proj: mat4x4<f32>,
    prev_view_proj: mat4x4<f32>,
    eye: vec4<f32>,
    light_direction: vec4<f32>,   // xyz: direction the light travels
    light_color: vec4<f32>,
    ambient: vec4<f32>,
    // x: texture mip bias, y: 1 when motion vectors are written
    params: vec4<f32>,
}

struct Material {
    base_color: vec4<f32>,
    specular: vec4<f32>,    // rgb: specular colour, a: shininess
    // x: alpha cutoff, y: 1 when unlit, z: 1 when the material is alpha-masked
    params: vec4<f32>,
}

struct Object {
    model: mat4x4<f32>,
    prev_model: mat4x4<f32>,
    normal_matrix: mat4x4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;
@group(1) @binding(0) var<uniform> material: Material;
@group(1) @binding(1) var base_texture: texture_2d<f32>;
@group(1) @binding(2) var base_sampler: sampler;
@group(2) @binding(0) var<uniform> object: Object;

// True when the pipeline uses alpha-to-coverage instead of the alpha test.
override ALPHA_TO_COVERAGE: bool = false;

struct VertexInput {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
}

struct Shaded {
    clip: vec4<f32>,
    world_position: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
    current_clip: vec4<f32>,
    previous_clip: vec4<f32>,
}

fn shade_vertex(v: VertexInput) -> Shaded {
    var out: Shaded;
    let world = object.model * vec4<f32>(v.position, 1.0);
    out.clip = view.view_proj * world;
    out.world_position = world.xyz;
    out.normal = (object.normal_matrix * vec4<f32>(v.normal, 0.0)).xyz;
    out.uv = v.uv;
    out.current_clip = view.unjittered_view_proj * world;
    out.previous_clip = view.prev_view_proj * (object.prev_model * vec4<f32>(v.position, 1.0));
    return out;
}

struct FragmentOutput {
    @location(0) color: vec4<f32>,
    @location(1) motion: vec2<f32>,
}

fn clip_to_uv(clip: vec4<f32>) -> vec2<f32> {
    let ndc = clip.xy / clip.w;
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
}

fn shade_fragment(
    world_position: vec3<f32>,
    normal_in: vec3<f32>,
    uv: vec2<f32>,
    current_clip: vec4<f32>,
    previous_clip: vec4<f32>,
    front_facing: bool,
) -> FragmentOutput {
    let texel = textureSampleBias(base_texture, base_sampler, uv, view.params.x);
    let albedo = material.base_color.rgb * texel.rgb;
    var alpha = texel.a * material.base_color.a;
    // Material switches choose results with select, never code paths: lavapipe recompiles a
    // shader at every draw whose branch conditions read uniforms only (gpu/shader.rs).
    let masked = material.params.z > 0.5;
    if ALPHA_TO_COVERAGE {
        // Sharpened alpha-to-coverage: the cutoff maps to 50% coverage and the transition
        // spans about one pixel, so masked edges keep their shape in every mip level.
        let coverage = clamp((alpha - material.params.x) / max(fwidth(alpha), 1e-4) + 0.5, 0.0, 1.0);
        alpha = select(alpha, coverage, masked);
    } else if masked & (alpha < material.params.x) {
        discard;
    }

    var n = normalize(normal_in);
    if !front_facing {
        n = -n;
    }
    let l = -normalize(view.light_direction.xyz);
    let v = normalize(view.eye.xyz - world_position);
    let h = normalize(l + v);
    let n_dot_l = max(dot(n, l), 0.0);
    let diffuse = albedo * n_dot_l;
    var specular = vec3<f32>(0.0);
    if n_dot_l > 0.0 {
        specular = material.specular.rgb * pow(max(dot(n, h), 0.0), material.specular.a);
    }
    let lit = view.ambient.rgb * albedo + view.light_color.rgb * (diffuse + specular);
    let unlit = material.params.y > 0.5;
    let rgb = select(lit, albedo, unlit);

    var out: FragmentOutput;
    out.color = vec4<f32>(clamp(rgb, vec3<f32>(0.0), vec3<f32>(1.0)), alpha);
    // Motion in UV units from the previous frame's position to this one's, without jitter.
    out.motion = (clip_to_uv(current_clip) - clip_to_uv(previous_clip)) * view.params.y;
    return out;
}

// ---- centre interpolation -------------------------------------------------------------------

struct VaryingsCenter {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) current_clip: vec4<f32>,
    @location(4) previous_clip: vec4<f32>,
}

@vertex
fn vs_center(v: VertexInput) -> VaryingsCenter {
    let s = shade_vertex(v);
    return VaryingsCenter(s.clip, s.world_position, s.normal, s.uv, s.current_clip, s.previous_clip);
}

@fragment
fn fs_center(in: VaryingsCenter, @builtin(front_facing) front_facing: bool) -> FragmentOutput {
    return shade_fragment(in.world_position, in.normal, in.uv, in.current_clip, in.previous_clip, front_facing);
}

// ---- centroid texture coordinates -----------------------------------------------------------

struct VaryingsCentroid {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(perspective, centroid) uv: vec2<f32>,
    @location(3) current_clip: vec4<f32>,
    @location(4) previous_clip: vec4<f32>,
}

@vertex
fn vs_centroid(v: VertexInput) -> VaryingsCentroid {
    let s = shade_vertex(v);
    return VaryingsCentroid(s.clip, s.world_position, s.normal, s.uv, s.current_clip, s.previous_clip);
}

@fragment
fn fs_centroid(in: VaryingsCentroid, @builtin(front_facing) front_facing: bool) -> FragmentOutput {
    return shade_fragment(in.world_position, in.normal, in.uv, in.current_clip, in.previous_clip, front_facing);
}

// ---- per-sample shading ---------------------------------------------------------------------

struct VaryingsSample {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(perspective, sample) world_position: vec3<f32>,
    @location(1) @interpolate(perspective, sample) normal: vec3<f32>,
    @location(2) @interpolate(perspective, sample) uv: vec2<f32>,
    @location(3) @interpolate(perspective, sample) current_clip: vec4<f32>,
    @location(4) @interpolate(perspective, sample) previous_clip: vec4<f32>,
}

@vertex
fn vs_sample(v: VertexInput) -> VaryingsSample {
    let s = shade_vertex(v);
    return VaryingsSample(s.clip, s.world_position, s.normal, s.uv, s.current_clip, s.previous_clip);
}

@fragment
fn fs_sample(in: VaryingsSample, @builtin(front_facing) front_facing: bool) -> FragmentOutput {
    return shade_fragment(in.world_position, in.normal, in.uv, in.current_clip, in.previous_clip, front_facing);
}
