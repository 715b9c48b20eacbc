//! The `chart` scene: a flat resolution test chart in the plane z = 0, facing +Z, seen
//! head-on by a still camera, like an ISO 12233 chart. Its [`ChartLayout`] describes every
//! black shape as an exact polygon, so a later pass can compute the exact per-pixel area
//! coverage as ground truth; the chart mesh is built from that same layout, so the two never
//! disagree.
//!
//! # Geometry
//! Chart units: the chart spans x in -8..8 and y in -4.5..4.5 (16:9). The camera (vertical
//! field of view 30 degrees, on +Z at the distance where the view is exactly 9 units tall)
//! frames it edge to edge in a 16:9 image, so at 1280x720 one unit is
//! [`CHART_PIXELS_PER_UNIT_720P`] = 80 pixels. Sizes below are quoted in pixels at 1280x720.
//!
//! The chart is a grid of 3 x 2 cells of 384 x 320 px:
//! - top left: a Siemens star, 36 black wedges (72 sectors) of radius 152 px;
//! - top middle: slanted-edge bars (104 x 52 px) whose long edges lie at 3, 10, 30, 45 and
//!   87 degrees;
//! - top right: a zone plate, 320 px square, textured (1024 texels, see [`ZonePlate`]);
//! - bottom left: discs of radius 48 px down to 0.375 px, and concentric rings with line
//!   widths 3 to 0.4 px;
//! - bottom middle: groups of three parallel lines whose widths narrow from 3 px to 0.1 px,
//!   near-vertical (2 degrees off) and near-horizontal;
//! - bottom right: two fine grids, 0.5 px lines at a 3 px pitch (axis-aligned) and 1 px
//!   lines at a 5 px pitch (rotated 7 degrees).
//!
//! # Rendering
//! Every material is unlit, so a pixel's value is exactly its coverage-weighted colour: the
//! background (clear colour) is white, the shapes black. The black polygons are pairwise
//! interior-disjoint (grid lines are split where they cross), so the black coverage of an
//! image area is the sum of the polygons' areas inside it.

use glam::{Vec2, Vec3};

use super::SceneOptions;
use super::geometry::MeshBuilder;
use super::texture::encode_srgb;
use crate::scene::{CameraRig, DirectionalLight, Material, Scene, TextureImage, Vertex};

/// Pixels per chart unit in a 1280x720 render of the chart camera (any image height H gives
/// H / 9).
pub const CHART_PIXELS_PER_UNIT_720P: f32 = 80.0;

/// One pixel at 1280x720, in chart units.
const PX: f32 = 1.0 / CHART_PIXELS_PER_UNIT_720P;
/// Half the chart's width and height.
const HALF_EXTENT: Vec2 = Vec2::new(8.0, 4.5);
/// Vertical field of view of the chart camera, degrees.
const FOV_Y_DEGREES: f32 = 30.0;
/// Cell centres: columns at x = -5.2, 0, 5.2; rows at y = +-13/6 (gaps of 1/3 unit).
const COLUMNS: [f32; 3] = [-5.2, 0.0, 5.2];
const ROWS: [f32; 2] = [13.0 / 6.0, -13.0 / 6.0];
/// Texels across the zone plate's texture.
const ZONE_PLATE_TEXELS: u32 = 1024;
/// Highest zone-plate frequency in the texture (at its corners), cycles per texel; kept
/// below 0.5 so the texture itself does not alias.
const ZONE_PLATE_MAX_CYCLES_PER_TEXEL: f32 = 0.45;

/// Which test a polygon belongs to (and the zoom category it serves).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ChartFeature {
    /// Wedges of the Siemens star (shape preservation, fine detail at the centre).
    SiemensStar,
    /// Slanted-edge bars (diagonals).
    SlantedEdge,
    /// Discs of decreasing radius (shape preservation).
    Disc,
    /// Segments of thin concentric rings (shape preservation of thin curves).
    Ring,
    /// Parallel lines narrowing below a pixel (fine geometry).
    LineGroup,
    /// Fine grid lines (multiple edges).
    Grid,
}

/// A black convex polygon of the chart.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartPolygon {
    /// Test the polygon belongs to.
    pub feature: ChartFeature,
    /// Vertices in chart units, counter-clockwise, convex, at least three.
    pub points: Vec<Vec2>,
}

impl ChartPolygon {
    /// Signed area (positive for counter-clockwise), chart units squared.
    pub fn area(&self) -> f32 {
        signed_area(&self.points)
    }
}

/// Shoelace area of a polygon, positive when counter-clockwise.
fn signed_area(points: &[Vec2]) -> f32 {
    let n = points.len();
    (0..n)
        .map(|i| points[i].perp_dot(points[(i + 1) % n]))
        .sum::<f32>()
        * 0.5
}

/// The bounding box and label of one test element, for zoomed crops and reports.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartRegion {
    /// What the element is, e.g. "slanted edge 3 deg" or "lines 0.25 px".
    pub label: String,
    /// Its test.
    pub feature: ChartFeature,
    /// Lower-left corner, chart units.
    pub min: Vec2,
    /// Upper-right corner, chart units.
    pub max: Vec2,
}

/// The zone plate: a textured square whose linear intensity at distance r (in texels) from
/// its centre is `0.5 + 0.5 cos(k r^2)`, i.e. a local frequency of `k r / pi` cycles per
/// texel, reaching 0.45 cycles per texel at the corners (about 1.1 cycles per pixel at
/// 1280x720 at the edge midpoints: past the Nyquist limit for the outer half of the plate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZonePlate {
    /// Lower-left corner, chart units.
    pub min: Vec2,
    /// Upper-right corner, chart units.
    pub max: Vec2,
    /// Texels across the (square) texture.
    pub texels: u32,
    /// The constant k, radians per texel squared.
    pub k: f32,
}

impl ZonePlate {
    /// Linear intensity (0..1) of the ideal pattern at a chart point. The texture holds this
    /// function sampled at texel centres (sRGB-encoded, 8 bits).
    pub fn intensity(&self, point: Vec2) -> f32 {
        let texels_per_unit = self.texels as f32 / (self.max.x - self.min.x);
        let r = (point - (self.min + self.max) * 0.5) * texels_per_unit;
        0.5 + 0.5 * (self.k * r.length_squared()).cos()
    }

    /// The texture: texel (i, j) (row j from the top) holds the intensity at its centre.
    fn texture(&self) -> TextureImage {
        let n = self.texels;
        let size = self.max - self.min;
        let mut image = image::RgbaImage::new(n, n);
        for (i, j, pixel) in image.enumerate_pixels_mut() {
            let point = Vec2::new(
                self.min.x + (i as f32 + 0.5) / n as f32 * size.x,
                self.max.y - (j as f32 + 0.5) / n as f32 * size.y,
            );
            let v = encode_srgb(self.intensity(point));
            *pixel = image::Rgba([v, v, v, 255]);
        }
        TextureImage {
            label: "chart zone plate".to_owned(),
            image,
        }
    }
}

/// Everything drawn on the chart, in chart units (x right, y up, z = 0).
///
/// To compute exact ground truth for an image of W x H pixels rendered with the chart's
/// camera (frame 0; the camera never moves): pixel (i, j) (column i, row j from the top)
/// covers the chart square between `chart_point((W, H), Vec2::new(i, j))` and
/// `chart_point((W, H), Vec2::new(i + 1, j + 1))` (see [`ChartLayout::chart_point`]).
/// Its black coverage is the sum over `polygons` of the area of (polygon ∩ pixel square)
/// divided by the square's area (the polygons never overlap), and its linear value is
/// `1 - coverage`; inside the zone plate the value is the area average of
/// [`ZonePlate::intensity`] instead (the rendered plate additionally goes through 8-bit
/// texels and the renderer's mip filtering). Encode to sRGB to compare with a render.
#[derive(Clone, Debug, PartialEq)]
pub struct ChartLayout {
    /// Lower-left corner of the chart.
    pub min: Vec2,
    /// Upper-right corner of the chart.
    pub max: Vec2,
    /// The black polygons.
    pub polygons: Vec<ChartPolygon>,
    /// Bounding boxes of the test elements.
    pub regions: Vec<ChartRegion>,
    /// The zone plate.
    pub zone_plate: ZonePlate,
}

impl ChartLayout {
    /// The chart point at an image position (pixels from the top-left corner, fractional) of
    /// a `size` image rendered with the chart camera. Exact for any aspect ratio: the camera
    /// always shows the chart's full height, centred.
    pub fn chart_point(&self, size: (u32, u32), pixel: Vec2) -> Vec2 {
        let units_per_pixel = (self.max.y - self.min.y) / size.1.max(1) as f32;
        let center = Vec2::new(size.0 as f32, size.1 as f32) * 0.5;
        let offset = (pixel - center) * units_per_pixel;
        (self.min + self.max) * 0.5 + Vec2::new(offset.x, -offset.y)
    }

    /// Total black area, chart units squared.
    pub fn black_area(&self) -> f32 {
        self.polygons.iter().map(ChartPolygon::area).sum()
    }
}

/// Collects polygons and their regions.
struct LayoutBuilder {
    polygons: Vec<ChartPolygon>,
    regions: Vec<ChartRegion>,
}

impl LayoutBuilder {
    /// Adds one test element made of `polygons`, recording its bounding box.
    fn element(&mut self, label: String, feature: ChartFeature, polygons: Vec<Vec<Vec2>>) {
        let points = || polygons.iter().flatten().copied();
        let min = points().fold(Vec2::splat(f32::MAX), Vec2::min);
        let max = points().fold(Vec2::splat(f32::MIN), Vec2::max);
        self.regions.push(ChartRegion {
            label,
            feature,
            min,
            max,
        });
        self.polygons.extend(
            polygons
                .into_iter()
                .filter(|p| p.len() >= 3)
                .map(|points| ChartPolygon { feature, points }),
        );
    }
}

/// A rectangle centred at `center`, `length` along unit `direction`, `width` across,
/// counter-clockwise.
fn bar(center: Vec2, direction: Vec2, length: f32, width: f32) -> Vec<Vec2> {
    let along = direction * length * 0.5;
    let across = direction.perp() * width * 0.5;
    vec![
        center - along - across,
        center + along - across,
        center + along + across,
        center - along + across,
    ]
}

/// A regular polygon approximating a circle (counter-clockwise).
fn disc(center: Vec2, radius: f32, sides: u32) -> Vec<Vec2> {
    (0..sides)
        .map(|k| {
            center + Vec2::from_angle(k as f32 / sides as f32 * std::f32::consts::TAU) * radius
        })
        .collect()
}

/// Clips a convex counter-clockwise polygon to an axis-aligned rectangle (Sutherland-Hodgman).
fn clip_to_rect(polygon: &[Vec2], min: Vec2, max: Vec2) -> Vec<Vec2> {
    // Each boundary as (axis, limit, keep the side where coordinate >= limit when sign = 1).
    let bounds = [
        (0, min.x, 1.0),
        (0, max.x, -1.0),
        (1, min.y, 1.0),
        (1, max.y, -1.0),
    ];
    let mut out = polygon.to_vec();
    for (axis, limit, sign) in bounds {
        let inside = |p: Vec2| (p[axis] - limit) * sign >= 0.0;
        let input = std::mem::take(&mut out);
        for (i, &p) in input.iter().enumerate() {
            let q = input[(i + 1) % input.len()];
            if inside(p) {
                out.push(p);
            }
            if inside(p) != inside(q) {
                let t = (limit - p[axis]) / (q[axis] - p[axis]);
                out.push(p + (q - p) * t);
            }
        }
        if out.is_empty() {
            break;
        }
    }
    // A vertex on a boundary is emitted twice (as itself and as the crossing); keep one.
    out.dedup_by(|a, b| a.distance_squared(*b) < 1e-12);
    if out.len() > 1 && out[0].distance_squared(out[out.len() - 1]) < 1e-12 {
        out.pop();
    }
    out
}

fn siemens_star(layout: &mut LayoutBuilder) {
    const WEDGES: u32 = 36;
    let center = Vec2::new(COLUMNS[0], ROWS[0]);
    let radius = 152.0 * PX;
    let sector = std::f32::consts::PI / WEDGES as f32;
    let wedges = (0..WEDGES)
        .map(|k| {
            let a = 2.0 * k as f32 * sector;
            vec![
                center,
                center + Vec2::from_angle(a) * radius,
                center + Vec2::from_angle(a + sector) * radius,
            ]
        })
        .collect();
    layout.element(
        format!("Siemens star, {WEDGES} wedges"),
        ChartFeature::SiemensStar,
        wedges,
    );
}

fn slanted_edges(layout: &mut LayoutBuilder) {
    let (x, y) = (COLUMNS[1], ROWS[0]);
    let bars = [
        (3.0f32, Vec2::new(x - 1.55, y + 0.95)),
        (10.0, Vec2::new(x, y + 0.95)),
        (30.0, Vec2::new(x + 1.55, y + 0.95)),
        (45.0, Vec2::new(x - 0.8, y - 1.0)),
        (87.0, Vec2::new(x + 0.8, y - 1.0)),
    ];
    for (degrees, center) in bars {
        let direction = Vec2::from_angle(degrees.to_radians());
        layout.element(
            format!("slanted edge {degrees} deg"),
            ChartFeature::SlantedEdge,
            vec![bar(center, direction, 104.0 * PX, 52.0 * PX)],
        );
    }
}

fn discs_and_rings(layout: &mut LayoutBuilder) {
    let (x, y) = (COLUMNS[0], ROWS[1]);
    let discs = [
        (48.0, Vec2::new(x - 1.7, y + 1.2)),
        (24.0, Vec2::new(x - 0.6, y + 1.2)),
        (12.0, Vec2::new(x + 0.15, y + 1.2)),
        (6.0, Vec2::new(x + 0.65, y + 1.2)),
        (3.0, Vec2::new(x - 2.0, y)),
        (1.5, Vec2::new(x - 1.5, y)),
        (0.75, Vec2::new(x - 1.0, y)),
        (0.375, Vec2::new(x - 0.5, y)),
    ];
    for (radius_px, center) in discs {
        layout.element(
            format!("disc radius {radius_px} px"),
            ChartFeature::Disc,
            vec![disc(center, radius_px * PX, 128)],
        );
    }
    let center = Vec2::new(x + 1.2, y - 0.75);
    for (radius_px, width_px) in [(88.0, 3.0), (66.0, 1.5), (44.0, 0.75), (22.0, 0.4)] {
        const SEGMENTS: u32 = 128;
        let (inner, outer) = (
            (radius_px - width_px * 0.5) * PX,
            (radius_px + width_px * 0.5) * PX,
        );
        let step = std::f32::consts::TAU / SEGMENTS as f32;
        let segments = (0..SEGMENTS)
            .map(|k| {
                let (a, b) = (
                    Vec2::from_angle(k as f32 * step),
                    Vec2::from_angle((k + 1) as f32 * step),
                );
                vec![
                    center + a * inner,
                    center + a * outer,
                    center + b * outer,
                    center + b * inner,
                ]
            })
            .collect();
        layout.element(
            format!("ring radius {radius_px} px, {width_px} px wide"),
            ChartFeature::Ring,
            segments,
        );
    }
}

fn line_groups(layout: &mut LayoutBuilder) {
    const WIDTHS_PX: [f32; 10] = [3.0, 2.0, 1.5, 1.0, 0.7, 0.5, 0.35, 0.25, 0.18, 0.1];
    const LINES: u32 = 3;
    const GAP_PX: f32 = 3.5;
    const GROUP_GAP_PX: f32 = 10.0;
    let tilt = 2f32.to_radians();
    let cell_left = COLUMNS[1] - 2.4;
    // Near-vertical lines (290 px long) on the left of the cell, advancing to the right;
    // near-horizontal lines (170 px) on the right, advancing downwards.
    let sets = [
        (
            "vertical",
            Vec2::new(tilt.sin(), tilt.cos()),
            Vec2::X,
            Vec2::new(cell_left + 6.0 * PX, ROWS[1]),
            290.0 * PX,
        ),
        (
            "horizontal",
            Vec2::new(tilt.cos(), -tilt.sin()),
            Vec2::NEG_Y,
            Vec2::new(cell_left + 298.0 * PX, ROWS[1] + 96.0 * PX),
            170.0 * PX,
        ),
    ];
    for (name, along, advance, start, length) in sets {
        let mut offset = 0.0;
        for width_px in WIDTHS_PX {
            let width = width_px * PX;
            let lines = (0..LINES)
                .map(|i| {
                    let across = offset + width * 0.5 + i as f32 * (width + GAP_PX * PX);
                    // `start` is the centre of the set's first edge; lines are centred on it.
                    bar(start + advance * across, along, length, width)
                })
                .collect();
            layout.element(
                format!("{name} lines {width_px} px"),
                ChartFeature::LineGroup,
                lines,
            );
            offset += LINES as f32 * width + (LINES - 1) as f32 * GAP_PX * PX + GROUP_GAP_PX * PX;
        }
    }
}

/// A grid of lines `width` wide at `pitch`, rotated by `degrees` about `center` and clipped
/// to the square of side `side` around it. Crossings are not drawn twice: the lines of one
/// direction run through, those of the other are split between them.
fn grid(layout: &mut LayoutBuilder, center: Vec2, side: f32, pitch: f32, width: f32, degrees: f32) {
    let rotation = Vec2::from_angle(degrees.to_radians());
    let to_chart = |p: Vec2| center + rotation.rotate(p);
    // Enough lines to cover the clip square in any rotation.
    let reach = side * std::f32::consts::SQRT_2 * 0.5 + pitch;
    let count = (reach / pitch).ceil() as i32;
    let positions: Vec<f32> = (-count..=count).map(|k| (k as f32 + 0.5) * pitch).collect();
    let half = width * 0.5;
    let rect =
        |lo: Vec2, hi: Vec2| [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)].map(to_chart);
    let mut pieces: Vec<[Vec2; 4]> = Vec::new();
    for &u in &positions {
        pieces.push(rect(
            Vec2::new(u - half, -reach),
            Vec2::new(u + half, reach),
        ));
    }
    for &v in &positions {
        let mut left = -reach;
        for &u in &positions {
            pieces.push(rect(
                Vec2::new(left, v - half),
                Vec2::new(u - half, v + half),
            ));
            left = u + half;
        }
        pieces.push(rect(Vec2::new(left, v - half), Vec2::new(reach, v + half)));
    }
    let clip_half = Vec2::splat(side * 0.5);
    let polygons = pieces
        .iter()
        .map(|piece| clip_to_rect(piece, center - clip_half, center + clip_half))
        .filter(|p| p.len() >= 3 && signed_area(p) > 1e-9)
        .collect();
    layout.element(
        format!(
            "grid {} px lines, {} px pitch, {degrees} deg",
            width / PX,
            pitch / PX
        ),
        ChartFeature::Grid,
        polygons,
    );
}

/// The chart's layout (see the module docs); [`chart`] draws exactly this.
pub fn chart_layout() -> ChartLayout {
    let mut layout = LayoutBuilder {
        polygons: Vec::new(),
        regions: Vec::new(),
    };
    siemens_star(&mut layout);
    slanted_edges(&mut layout);
    discs_and_rings(&mut layout);
    line_groups(&mut layout);
    let (x, y) = (COLUMNS[2], ROWS[1]);
    grid(
        &mut layout,
        Vec2::new(x - 1.2, y),
        2.2,
        3.0 * PX,
        0.5 * PX,
        0.0,
    );
    grid(
        &mut layout,
        Vec2::new(x + 1.2, y),
        2.2,
        5.0 * PX,
        1.0 * PX,
        7.0,
    );
    let plate_center = Vec2::new(COLUMNS[2], ROWS[0]);
    let texels = ZONE_PLATE_TEXELS;
    let corner_radius = texels as f32 * std::f32::consts::FRAC_1_SQRT_2;
    ChartLayout {
        min: -HALF_EXTENT,
        max: HALF_EXTENT,
        polygons: layout.polygons,
        regions: layout.regions,
        zone_plate: ZonePlate {
            min: plate_center - Vec2::splat(2.0),
            max: plate_center + Vec2::splat(2.0),
            texels,
            k: std::f32::consts::PI * ZONE_PLATE_MAX_CYCLES_PER_TEXEL / corner_radius,
        },
    }
}

/// The chart scene (see the module docs). `options` are ignored: the chart is fixed.
pub fn chart(_options: &SceneOptions) -> Scene {
    let layout = chart_layout();
    let triangles: usize = layout.polygons.iter().map(|p| p.points.len() - 2).sum();
    let vertices: usize = layout.polygons.iter().map(|p| p.points.len()).sum();
    let mut shapes = MeshBuilder::with_capacity(vertices, triangles);
    for polygon in &layout.polygons {
        let first = shapes.vertices.len() as u32;
        for &p in &polygon.points {
            shapes.vertex(p.extend(0.0), Vec3::Z, [0.0, 0.0]);
        }
        for k in 1..polygon.points.len() as u32 - 1 {
            shapes.triangle(first, first + k, first + k + 1);
        }
    }
    let plate = layout.zone_plate;
    let mut zone_plate = MeshBuilder::with_capacity(4, 2);
    let corners = [
        (Vec2::new(plate.min.x, plate.min.y), [0.0, 1.0]),
        (Vec2::new(plate.max.x, plate.min.y), [1.0, 1.0]),
        (Vec2::new(plate.max.x, plate.max.y), [1.0, 0.0]),
        (Vec2::new(plate.min.x, plate.max.y), [0.0, 0.0]),
    ];
    zone_plate
        .vertices
        .extend(corners.map(|(p, uv)| Vertex::new(p.extend(0.0), Vec3::Z, uv)));
    zone_plate.quad(0, 1, 2, 3);
    let unlit = |name: &str, base_color: Vec3, texture: Option<usize>| Material {
        name: name.to_owned(),
        base_color,
        base_color_texture: texture,
        unlit: true,
        double_sided: false,
        ..Material::default()
    };
    Scene {
        name: "chart".to_owned(),
        meshes: vec![
            shapes.build("chart shapes", 0, None),
            zone_plate.build("chart zone plate", 1, None),
        ],
        materials: vec![
            unlit("chart black", Vec3::ZERO, None),
            unlit("chart zone plate", Vec3::ONE, Some(0)),
        ],
        textures: vec![plate.texture()],
        camera: CameraRig {
            target: Vec3::ZERO,
            distance: HALF_EXTENT.y / (FOV_Y_DEGREES * 0.5).to_radians().tan(),
            yaw_degrees: 0.0,
            pitch_degrees: 0.0,
            fov_y_degrees: FOV_Y_DEGREES,
            near: 1.0,
            far: 100.0,
            orbit_degrees_per_frame: 0.0,
        },
        interior: false,
        light: DirectionalLight::default(),
        clear_color: Vec3::ONE,
        views: Vec::new(),
        notes: Vec::new(),
        warnings: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::camera::FrameCamera;
    use crate::scene::procedural::tests::assert_scene_valid;

    #[test]
    fn polygons_are_convex_counter_clockwise_and_on_the_chart() {
        let layout = chart_layout();
        assert!(layout.polygons.len() > 100);
        for polygon in &layout.polygons {
            let n = polygon.points.len();
            assert!(n >= 3);
            for i in 0..n {
                let [a, b, c] = [0, 1, 2].map(|k| polygon.points[(i + k) % n]);
                // Every turn is to the left (or straight, for clipped collinear points).
                assert!((b - a).perp_dot(c - b) >= -1e-9, "{polygon:?}");
                assert!(a.abs().cmple(HALF_EXTENT).all(), "{a}");
            }
            assert!(polygon.area() > 0.0);
        }
        for region in &layout.regions {
            let outside_plate = region.max.x < layout.zone_plate.min.x
                || region.min.y > layout.zone_plate.max.y
                || region.max.y < layout.zone_plate.min.y;
            assert!(outside_plate, "{region:?} overlaps the zone plate");
        }
    }

    /// Rasterises the layout at 2x2 samples per 1280x720 pixel and checks that no sample is
    /// inside two polygons (the ground truth relies on it) and that the sample count matches
    /// the area.
    #[test]
    fn polygons_do_not_overlap() {
        let layout = chart_layout();
        let (w, h) = (2560usize, 1440usize);
        let mut hits = vec![0u8; w * h];
        let to_sample =
            |p: Vec2| (p - layout.min) / (layout.max - layout.min) * Vec2::new(w as f32, h as f32);
        for polygon in &layout.polygons {
            let lo = polygon
                .points
                .iter()
                .copied()
                .fold(Vec2::splat(f32::MAX), Vec2::min);
            let hi = polygon
                .points
                .iter()
                .copied()
                .fold(Vec2::splat(f32::MIN), Vec2::max);
            let (lo, hi) = (to_sample(lo).floor(), to_sample(hi).ceil());
            for y in lo.y.max(0.0) as usize..(hi.y as usize).min(h) {
                for x in lo.x.max(0.0) as usize..(hi.x as usize).min(w) {
                    // Sample positions offset from pixel centres so that none falls on a
                    // shared edge or the star's apex.
                    let s = Vec2::new(x as f32 + 0.5013, y as f32 + 0.4987);
                    let p =
                        layout.min + s / Vec2::new(w as f32, h as f32) * (layout.max - layout.min);
                    let n = polygon.points.len();
                    let inside = (0..n).all(|i| {
                        (polygon.points[(i + 1) % n] - polygon.points[i])
                            .perp_dot(p - polygon.points[i])
                            > 0.0
                    });
                    if inside {
                        hits[y * w + x] += 1;
                    }
                }
            }
        }
        assert!(hits.iter().all(|&c| c <= 1), "overlapping polygons");
        let sample_area = (layout.max - layout.min).element_product() / (w * h) as f32;
        let covered = hits.iter().filter(|&&c| c == 1).count() as f32 * sample_area;
        let area = layout.black_area();
        assert!((covered - area).abs() < 0.02 * area, "{covered} vs {area}");
    }

    #[test]
    fn mesh_matches_the_layout() {
        let scene = chart(&SceneOptions::default());
        assert_scene_valid(&scene);
        let layout = chart_layout();
        let black = &scene.meshes[0];
        let mesh_area: f64 = black
            .indices
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] =
                    [0, 1, 2].map(|k| Vec3::from(black.vertices[t[k] as usize].position));
                assert_eq!(a.z, 0.0);
                f64::from((b - a).cross(c - a).z) * 0.5
            })
            .sum();
        let layout_area = f64::from(layout.black_area());
        assert!(
            (mesh_area - layout_area).abs() < 1e-4 * layout_area,
            "{mesh_area} {layout_area}"
        );
        assert!(scene.materials.iter().all(|m| m.unlit));
        assert_eq!(scene.materials[0].base_color, Vec3::ZERO);
        assert_eq!(scene.clear_color, Vec3::ONE);
        let texture = &scene.textures[0].image;
        assert_eq!(texture.dimensions(), (ZONE_PLATE_TEXELS, ZONE_PLATE_TEXELS));
    }

    #[test]
    fn camera_frames_the_chart_edge_to_edge() {
        let scene = chart(&SceneOptions::default());
        let layout = chart_layout();
        let size = (1280, 720);
        let camera = FrameCamera::from_rig(&scene.camera, 0, size);
        let view_proj = camera.view_proj();
        for pixel in [
            Vec2::ZERO,
            Vec2::new(1280.0, 720.0),
            Vec2::new(100.5, 600.25),
        ] {
            let point = layout.chart_point(size, pixel);
            let clip = view_proj * point.extend(0.0).extend(1.0);
            let ndc = clip.truncate() / clip.w;
            let projected = Vec2::new((ndc.x + 1.0) * 640.0, (1.0 - ndc.y) * 360.0);
            assert!(
                (projected - pixel).length() < 0.01,
                "{pixel} -> {projected}"
            );
        }
        assert_eq!(layout.chart_point(size, Vec2::ZERO), Vec2::new(-8.0, 4.5));
        let width =
            layout.chart_point(size, Vec2::new(1280.0, 0.0)) - layout.chart_point(size, Vec2::ZERO);
        assert!((1280.0 / width.x - CHART_PIXELS_PER_UNIT_720P).abs() < 1e-3);
    }

    #[test]
    fn line_widths_reach_a_tenth_of_a_pixel() {
        let layout = chart_layout();
        let narrowest = layout
            .polygons
            .iter()
            .filter(|p| p.feature == ChartFeature::LineGroup)
            .map(|p| p.points[0].distance(p.points[3]))
            .fold(f32::MAX, f32::min);
        assert!(
            (narrowest * CHART_PIXELS_PER_UNIT_720P - 0.1).abs() < 1e-3,
            "{narrowest}"
        );
    }

    #[test]
    fn zone_plate_texture_follows_the_formula() {
        let layout = chart_layout();
        let plate = layout.zone_plate;
        let texture = plate.texture();
        let centre = texture.image.get_pixel(512, 512)[0];
        assert!(centre >= 254, "{centre}");
        // The frequency at the corner stays below the texture's own Nyquist limit.
        let corner_radius = 512.0 * std::f32::consts::SQRT_2;
        let cycles_per_texel = plate.k * corner_radius / std::f32::consts::PI;
        assert!(cycles_per_texel < 0.5 && cycles_per_texel > 0.4);
        // At 1280x720 the plate is 320 px for 1024 texels: Nyquist (0.5 cycles/px) is passed
        // inside the plate.
        let cycles_per_px_at_edge = plate.k * 512.0 / std::f32::consts::PI * 1024.0 / 320.0;
        assert!(cycles_per_px_at_edge > 1.0);
        for (i, j) in [(3, 5), (76, 179), (700, 1000), (1023, 0)] {
            let centre = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) / 1024.0 * 4.0;
            let v = plate.intensity(Vec2::new(plate.min.x + centre.x, plate.max.y - centre.y));
            assert_eq!(texture.image.get_pixel(i, j)[0], encode_srgb(v));
        }
    }
}
