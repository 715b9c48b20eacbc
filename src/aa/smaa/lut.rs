//! The two SMAA lookup tables, generated here from their geometric rules (never shipped as
//! opaque binary blobs) once per process and cached.
//!
//! # Area table (160 x 560, two channels)
//! For an edge run found by the blending-weight pass, the table answers how much of the current
//! pixel the colour across the edge covers (channel 0) and how much of the pixel across the edge
//! the current pixel's colour covers (channel 1). It holds seven 80-row sub-tables, one per
//! sub-sample offset (SMAA 1x uses offset 0; the temporal and multisample modes use the others,
//! see [`subsample_indices`]).
//!
//! - **Orthogonal part** (x 0..80 of each sub-table): the run is revectorised into a line
//!   through the middle of the crossing edges at its ends ([`Crossing`]), moved by the
//!   sub-sample offset: an L goes from its crossed end to the middle of the run, a Z is one
//!   line end to end, a U two halves meeting in the middle (rounded for short runs); runs
//!   without crossings are never filtered, so pixel-aligned edges stay sharp. The area between
//!   the line and the edge over each pixel is integrated exactly ([`ortho_area`]). The 16
//!   crossing combinations occupy 16 x 16 cells of a 5 x 5 grid at cell `3 * current +
//!   opposite`; texel `(i, j)` of a cell holds distances `(i^2, j^2)`, so bilinear filtering at
//!   `sqrt(distance)` covers distances up to 225 pixels with 16 texels.
//! - **Diagonal part** (x 80..160, five sub-tables): 45-degree staircases, in a frame rotated
//!   so that the staircase zig-zags about the line v = 1/2; each end stops ([`DiagonalEnd`]),
//!   continues vertically or horizontally (the line bends through the middle of the step, as an
//!   orthogonal L does), or both. Areas are measured by brute force with 30 x 30 samples per
//!   pixel ([`diag_area`]); cells are 20 x 20 (distances 0..19, linear) in a 4 x 4 grid at
//!   `(near end, far end)`.
//!
//! # Search table (64 x 16, one channel)
//! The orthogonal search reads edges two pixels at a time with a bilinear fetch placed so that
//! the four edges it covers get distinct weights (21, 7, 3 and 1 out of 32). When the search
//! stops, the table decodes the last fetch of both channels (followed and crossing edges) into
//! how many of those two pixels still belong to the run (0, 1 or 2, stored as 127 per pixel;
//! [`search_texel`] gives where each answer lives). Rows that all mean "the near pixel has no
//! edge" are dropped; the shader reads zero for a texel off the table.
//!
//! The full geometry, step by step: `docs/techniques/smaa.md`.

use std::sync::OnceLock;

use crate::aa::common::morphology::{Crossing, polyline_area};

/// Size of the area table in texels.
pub const AREA_SIZE: (u32, u32) = (160, 560);
/// Size of the search table in texels.
pub const SEARCH_SIZE: (u32, u32) = (64, 16);
/// Side of one orthogonal cell: texel i stands for a distance of i^2 pixels.
pub const ORTHO_CELL: u32 = 16;
/// Side of one diagonal cell: texel i stands for a distance of i pixels.
pub const DIAG_CELL: u32 = 20;
/// Height of one sub-table (one sub-sample offset).
pub const SUBTABLE_HEIGHT: u32 = 80;
/// The longest diagonal distance the table holds on each side of the current pixel.
pub const MAX_DIAG_DISTANCE: u32 = DIAG_CELL - 1;
/// Sub-sample offsets of the orthogonal sub-tables: the sample's shift across the edge, in
/// pixels, positive towards the pixel across the edge; the sample is taken to lie on the
/// diagonal through the pixel centre that the 2x patterns use, so it also moves by minus the
/// offset along the edge (see [`subsample_indices`]).
pub const ORTHO_OFFSETS: [f32; 7] = [0.0, -0.25, 0.25, -0.125, 0.125, -0.375, 0.375];
/// Sub-sample offsets of the diagonal sub-tables: the sample's position inside the pixel
/// relative to its centre (x right, y up) in the frame of the `/` staircase. Only the part
/// across the staircase matters, a shift of the line by `x - y` in `v`.
pub const DIAG_OFFSETS: [(f32, f32); 5] = [
    (0.0, 0.0),
    (0.25, -0.25),
    (-0.25, 0.25),
    (0.125, -0.125),
    (-0.125, 0.125),
];
/// Samples per pixel side for the diagonal areas.
const DIAG_SAMPLES: i32 = 30;
/// U shapes shorter than this are rounded.
const SMOOTH_MAX_DISTANCE: f32 = 32.0;
/// Search table value of one extra pixel.
pub const SEARCH_UNIT: u8 = 127;

/// How a diagonal run continues past one of its ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiagonalEnd {
    /// The staircase stops there, or its end lies beyond the search.
    Open,
    /// The outline continues with a vertical step.
    Vertical,
    /// The outline continues with a horizontal step.
    Horizontal,
    /// Both: a junction, treated as open.
    Both,
}

impl DiagonalEnd {
    /// Every value, in cell order.
    pub const ALL: [Self; 4] = [Self::Open, Self::Vertical, Self::Horizontal, Self::Both];

    /// The end from the two continuation edges the shader reads.
    pub fn from_edges(vertical: bool, horizontal: bool) -> Self {
        Self::ALL[usize::from(vertical) + 2 * usize::from(horizontal)]
    }

    /// Cell index along one axis of the diagonal part: `vertical + 2 * horizontal`.
    pub fn cell(self) -> u32 {
        match self {
            Self::Open => 0,
            Self::Vertical => 1,
            Self::Horizontal => 2,
            Self::Both => 3,
        }
    }
}

/// Rounds the sharp tip of a short U: small areas are raised towards `sqrt(2a) / 2`, less
/// and less as the U gets longer.
fn smooth_u(length: f32, area: [f32; 2]) -> [f32; 2] {
    let exact = (length / SMOOTH_MAX_DISTANCE).min(1.0);
    area.map(|a| {
        let round = 0.5 * (2.0 * a).sqrt();
        round + (a - round) * exact
    })
}

fn plus(a: [f32; 2], b: [f32; 2]) -> [f32; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

/// Orthogonal areas (current pixel, pixel across the edge) for a run reaching `left` pixels
/// before and `right` pixels after the current one, with the given crossing edges, for a
/// sample shifted by `offset` across the edge (module docs).
pub fn ortho_area(start: Crossing, end: Crossing, left: f32, right: f32, offset: f32) -> [f32; 2] {
    let d = left + right + 1.0;
    let area = |points: &[(f32, f32)]| polyline_area(points, left, left + 1.0);
    let middle = (d * 0.5, 0.0);
    // A junction at one end continues the line to the other side of the other end.
    let (start, end) = match (start, end) {
        (Crossing::Both, Crossing::Current | Crossing::Opposite) => (end.flipped(), end),
        (Crossing::Current | Crossing::Opposite, Crossing::Both) => (start, start.flipped()),
        _ => (start, end),
    };
    // The samples sit `offset` across the edge and `-offset` along it (module docs), so the
    // crossings, halfway between two samples, move along the run too.
    let (x0, x1) = (-offset, d - offset);
    match (start.height(offset), end.height(offset)) {
        (None, None) => [0.0, 0.0],
        (Some(y), None) => area(&[(x0, y), middle]),
        (None, Some(y)) => area(&[middle, (x1, y)]),
        (Some(y0), Some(y1)) if start == end => {
            // U: two halves, each rounded when short.
            plus(
                smooth_u(d, area(&[(x0, y0), middle])),
                smooth_u(d, area(&[middle, (x1, y1)])),
            )
        }
        // Z (or a junction turned into one): one line from end to end. With a sub-sample
        // offset its middle lies off the edge, by the offset, where the samples put it.
        (Some(y0), Some(y1)) => area(&[(x0, y0), (x1, y1)]),
    }
}

/// The revectorised line of a diagonal run as a function `v(u)` (module docs), extended
/// flat beyond its ends.
fn diagonal_line(
    near: DiagonalEnd,
    far: DiagonalEnd,
    near_len: u32,
    far_len: u32,
    shift: f64,
) -> impl Fn(f64) -> f64 {
    let base = 0.5 + shift;
    let u_near = -2.0 * f64::from(near_len) - 1.0;
    let u_far = 2.0 * f64::from(far_len) + 1.0;
    let near_point = match near {
        DiagonalEnd::Vertical => Some((u_near, base + 0.5)),
        DiagonalEnd::Horizontal => Some((u_near - 1.0, base - 0.5)),
        _ => None,
    };
    let far_point = match far {
        DiagonalEnd::Horizontal => Some((u_far, base + 0.5)),
        DiagonalEnd::Vertical => Some((u_far + 1.0, base - 0.5)),
        _ => None,
    };
    let middle_u = (near_point.map_or(u_near, |p| p.0) + far_point.map_or(u_far, |p| p.0)) * 0.5;
    let middle = (middle_u, base);
    let mut points: Vec<(f64, f64)> = match (near_point, far_point) {
        (None, None) => vec![(u_near, base), (u_far, base)],
        (Some(n), None) => vec![n, middle],
        (None, Some(f)) => vec![middle, f],
        (Some(n), Some(f)) if n.1 == f.1 => vec![n, middle, f],
        (Some(n), Some(f)) => vec![n, f],
    };
    points.dedup_by(|a, b| a.0 == b.0);
    move |u: f64| {
        let first = points[0];
        let last = points[points.len() - 1];
        if u <= first.0 {
            return first.1;
        }
        if u >= last.0 {
            return last.1;
        }
        points.windows(2).find(|p| u <= p[1].0).map_or(last.1, |p| {
            p[0].1 + (p[1].1 - p[0].1) * (u - p[0].0) / (p[1].0 - p[0].0)
        })
    }
}

/// Fraction of the 30 x 30 samples of pixel `(px, py)` (y down) lying on one side of the line
/// `v = line(u)`: below it (`v < line`) or above; samples on the line count half.
///
/// Samples sit at `(i + 1/2) / 30`. The samples of one diagonal `i - j = k` share `u`, so the
/// line is evaluated once per diagonal and the samples below it are counted in closed form;
/// the count is identical to testing all 900 samples one by one.
fn diagonal_coverage(line: &impl Fn(f64) -> f64, px: i32, py: i32, below: bool) -> f32 {
    const EPS: f64 = 1e-6;
    let n = f64::from(DIAG_SAMPLES);
    let mut count = 0.0f64;
    for k in -(DIAG_SAMPLES - 1)..DIAG_SAMPLES {
        let u = f64::from(px - py) + f64::from(k) / n;
        // On this diagonal j runs over [lo, hi] and v = px + py + (2j + k + 1) / n.
        let (lo, hi) = ((-k).max(0), (DIAG_SAMPLES - 1).min(DIAG_SAMPLES - 1 - k));
        let total = f64::from(hi - lo + 1);
        let t = ((line(u) - f64::from(px + py)) * n - f64::from(k) - 1.0) * 0.5;
        // Samples with j < t are below the line, j == t on it.
        let below_count = |limit: f64| (limit.ceil() - f64::from(lo)).clamp(0.0, total);
        let strictly = below_count(t - EPS);
        let up_to = (((t + EPS).floor() - f64::from(lo)) + 1.0).clamp(0.0, total);
        let on = up_to - strictly;
        count += if below {
            strictly + 0.5 * on
        } else {
            total - up_to + 0.5 * on
        };
    }
    (count / (n * n)) as f32
}

/// Diagonal areas (current pixel, pixel above) for a `/` run reaching `near_len` pixels
/// down-left and `far_len` pixels up-right, with the given ends, for a sample offset
/// `offset` (x right, y up) in the frame of the run (module docs).
pub fn diag_area(
    near: DiagonalEnd,
    far: DiagonalEnd,
    near_len: u32,
    far_len: u32,
    offset: (f32, f32),
) -> [f32; 2] {
    let shift = f64::from(offset.0) - f64::from(offset.1);
    let line = diagonal_line(near, far, near_len, far_len, shift);
    [
        diagonal_coverage(&line, 0, 0, true),
        diagonal_coverage(&line, 0, -1, false),
    ]
}

/// The generated tables, tightly packed rows.
pub struct Tables {
    /// Area table, two bytes per texel (Rg8Unorm).
    pub area: Vec<u8>,
    /// Search table, one byte per texel (R8Unorm).
    pub search: Vec<u8>,
}

fn unorm8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

fn area_table() -> Vec<u8> {
    let (width, height) = AREA_SIZE;
    let mut data = vec![0u8; (width * height * 2) as usize];
    let mut put = |x: u32, y: u32, a: [f32; 2]| {
        let i = ((y * width + x) * 2) as usize;
        data[i] = unorm8(a[0]);
        data[i + 1] = unorm8(a[1]);
    };
    for (o, &offset) in ORTHO_OFFSETS.iter().enumerate() {
        let base_y = o as u32 * SUBTABLE_HEIGHT;
        for start in Crossing::ALL {
            for end in Crossing::ALL {
                for i in 0..ORTHO_CELL {
                    for j in 0..ORTHO_CELL {
                        let a = ortho_area(start, end, (i * i) as f32, (j * j) as f32, offset);
                        put(
                            start.cell() * ORTHO_CELL + i,
                            base_y + end.cell() * ORTHO_CELL + j,
                            a,
                        );
                    }
                }
            }
        }
    }
    for (o, &offset) in DIAG_OFFSETS.iter().enumerate() {
        let base_y = o as u32 * SUBTABLE_HEIGHT;
        for near in DiagonalEnd::ALL {
            for far in DiagonalEnd::ALL {
                for i in 0..DIAG_CELL {
                    for j in 0..DIAG_CELL {
                        let a = diag_area(near, far, i, j, offset);
                        put(
                            80 + near.cell() * DIAG_CELL + i,
                            base_y + far.cell() * DIAG_CELL + j,
                            a,
                        );
                    }
                }
            }
        }
    }
    data
}

/// The four edges one search fetch covers, from its value times 32, or `None` for a value no
/// combination produces. Order: far pixel opposite row, near opposite, far current, near
/// current (weights 1, 3, 7, 21).
pub fn decode_fetch(index: u32) -> Option<[bool; 4]> {
    (0u32..16)
        .map(|bits| [bits & 1 != 0, bits & 2 != 0, bits & 4 != 0, bits & 8 != 0])
        .find(|e| {
            u32::from(e[0]) + 3 * u32::from(e[1]) + 7 * u32::from(e[2]) + 21 * u32::from(e[3])
                == index
        })
}

/// Pixels of the last fetch that still belong to the run when searching backwards (the near
/// pixel lies towards the start): the near pixel if it has the edge, then the far one if it
/// has it too and no crossing edge separates them (the near pixel's own crossing edges).
pub fn extra_backward(crossing: [bool; 4], edge: [bool; 4]) -> u8 {
    let near = edge[3];
    let far = near && edge[2] && !crossing[1] && !crossing[3];
    u8::from(near) + u8::from(far)
}

/// The same when searching forwards: a pixel's crossing edges lie on its start side, so the
/// near pixel needs its own crossing edges clear and the far pixel its own.
pub fn extra_forward(crossing: [bool; 4], edge: [bool; 4]) -> u8 {
    let near = edge[3] && !crossing[1] && !crossing[3];
    let far = near && edge[2] && !crossing[0] && !crossing[2];
    u8::from(near) + u8::from(far)
}

/// Where the search table stores the entry for fetched indices (crossing, edge), or `None`
/// when it falls off the table.
pub fn search_texel(forward: bool, crossing_index: u32, edge_index: u32) -> Option<(u32, u32)> {
    let x = crossing_index + if forward { 33 } else { 0 };
    let y = 32u32.checked_sub(edge_index)?;
    (x < SEARCH_SIZE.0 && y < SEARCH_SIZE.1).then_some((x, y))
}

fn search_table() -> Vec<u8> {
    let (width, height) = SEARCH_SIZE;
    let mut data = vec![0u8; (width * height) as usize];
    for crossing_index in 0..=32 {
        for edge_index in 0..=32 {
            let (Some(crossing), Some(edge)) =
                (decode_fetch(crossing_index), decode_fetch(edge_index))
            else {
                continue;
            };
            for forward in [false, true] {
                let extra = if forward {
                    extra_forward(crossing, edge)
                } else {
                    extra_backward(crossing, edge)
                };
                if let Some((x, y)) = search_texel(forward, crossing_index, edge_index) {
                    data[(y * width + x) as usize] = extra * SEARCH_UNIT;
                }
            }
        }
    }
    data
}

/// The tables, generated on first use.
pub fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(|| Tables {
        area: area_table(),
        search: search_table(),
    })
}

/// Sub-table indices for a sample at `position` relative to the pixel centre (pixels, x right,
/// y down): [horizontal edges, vertical edges, `/` diagonals, `\` diagonals], each the
/// sub-table whose offset is nearest to the sample's shift in that frame.
///
/// Horizontal edges (current pixel below the edge) see the sample shifted by `-y` towards
/// the pixel across; vertical edges (current pixel right of the edge) by `-x`. The `/` frame
/// has y up, so its offset is `(x, -y)`; `\` diagonals are that frame mirrored, `(-x, -y)`.
/// The orthogonal sub-tables also move the sample along the edge by minus the offset, which
/// is exact for samples on the `\` diagonal through the centre (every position SMAA T2x and
/// S2x use) and an approximation elsewhere.
pub fn subsample_indices(position: glam::Vec2) -> [u32; 4] {
    let nearest_ortho = |shift: f32| nearest(ORTHO_OFFSETS.iter().map(|o| (o - shift).abs()));
    let nearest_diag = |x: f32, y: f32| {
        nearest(
            DIAG_OFFSETS
                .iter()
                .map(|(ox, oy)| ((ox - oy) - (x - y)).abs()),
        )
    };
    [
        nearest_ortho(-position.y),
        nearest_ortho(-position.x),
        nearest_diag(position.x, -position.y),
        nearest_diag(-position.x, -position.y),
    ]
}

fn nearest(distances: impl Iterator<Item = f32>) -> u32 {
    distances
        .enumerate()
        .fold((0, f32::INFINITY), |best, (i, d)| {
            if d < best.1 - 1e-6 { (i, d) } else { best }
        })
        .0 as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f32; 2], b: [f32; 2], tolerance: f32) -> bool {
        (a[0] - b[0]).abs() <= tolerance && (a[1] - b[1]).abs() <= tolerance
    }

    #[test]
    fn l_shape_areas_match_hand_computation() {
        // Crossing on the current side at the start, run of 4: the line falls from
        // (0, -1/2) to (2, 0). Pixel 0 is a trapezoid of heights 1/2 and 1/4.
        let l =
            |left: f32, right: f32| ortho_area(Crossing::Current, Crossing::None, left, right, 0.0);
        assert!(close(l(0.0, 3.0), [0.375, 0.0], 1e-6));
        assert!(close(l(1.0, 2.0), [0.125, 0.0], 1e-6));
        assert!(close(l(2.0, 1.0), [0.0, 0.0], 1e-6));
        // The same L on the other side of the edge fills the pixel across.
        let up = ortho_area(Crossing::Opposite, Crossing::None, 0.0, 3.0, 0.0);
        assert!(close(up, [0.0, 0.375], 1e-6));
        // A one-pixel run with one crossing: a triangle of height 1/2 and width 1/2.
        let single = ortho_area(Crossing::None, Crossing::Current, 0.0, 0.0, 0.0);
        assert!(close(single, [0.125, 0.0], 1e-6), "{single:?}");
    }

    #[test]
    fn z_and_u_shape_areas_match_hand_computation() {
        // Z of length 3 from (0, -1/2) to (3, 1/2): the middle pixel holds two triangles of
        // width 1/2 and height 1/6; the first pixel a trapezoid of heights 1/2 and 1/6.
        let z = |left: f32, right: f32| {
            ortho_area(Crossing::Current, Crossing::Opposite, left, right, 0.0)
        };
        assert!(close(z(1.0, 1.0), [1.0 / 24.0, 1.0 / 24.0], 1e-6));
        assert!(close(z(0.0, 2.0), [1.0 / 3.0, 0.0], 1e-6));
        assert!(close(z(2.0, 0.0), [0.0, 1.0 / 3.0], 1e-6));
        // A long U (no rounding at 32 pixels): halves from -1/2 to 0 over 16 pixels each.
        let u = ortho_area(Crossing::Current, Crossing::Current, 0.0, 31.0, 0.0);
        assert!(
            close(u, [(0.5 + 0.5 - 1.0 / 32.0) * 0.5, 0.0], 1e-6),
            "{u:?}"
        );
        // A short U is rounded upwards: the three-pixel U's end pixel.
        let short = ortho_area(Crossing::Current, Crossing::Current, 0.0, 2.0, 0.0);
        let exact = (0.5 + 0.5 - 1.0 / 3.0) * 0.5;
        assert!(short[0] > exact && short[0] <= 0.5, "{short:?}");
        // Junctions: with a plain end the run is left alone, with a crossing it becomes a Z.
        assert_eq!(
            ortho_area(Crossing::Both, Crossing::None, 0.0, 3.0, 0.0),
            [0.0, 0.0]
        );
        assert_eq!(
            ortho_area(Crossing::Both, Crossing::Current, 1.0, 1.0, 0.0),
            ortho_area(Crossing::Opposite, Crossing::Current, 1.0, 1.0, 0.0)
        );
    }

    #[test]
    fn ortho_areas_are_symmetric_and_in_range() {
        for (o, &offset) in ORTHO_OFFSETS.iter().enumerate() {
            for start in Crossing::ALL {
                for end in Crossing::ALL {
                    for left in 0..20 {
                        for right in 0..20 {
                            let (l, r) = (left as f32, right as f32);
                            let a = ortho_area(start, end, l, r, offset);
                            assert!(a.iter().all(|v| (0.0..=1.0).contains(v)), "{a:?}");
                            if offset == 0.0 {
                                assert!(a[0] <= 0.5 + 1e-6 && a[1] <= 0.5 + 1e-6, "{a:?}");
                            }
                            // Half a turn: the run reversed, sides swapped, the sample moved
                            // to the opposite point of the diagonal (offset negated).
                            let (fs, fe) = (start.flipped(), end.flipped());
                            let turned = ortho_area(fe, fs, r, l, -offset);
                            assert!(
                                close(a, [turned[1], turned[0]], 1e-5),
                                "turn {o} {start:?} {end:?} {l} {r}"
                            );
                            if offset == 0.0 {
                                // Centred samples: mirror images along and across the edge.
                                let m = ortho_area(end, start, r, l, 0.0);
                                assert!(close(a, m, 1e-5), "mirror {start:?} {end:?} {l} {r}");
                                let flipped = ortho_area(fs, fe, l, r, 0.0);
                                assert!(
                                    close(a, [flipped[1], flipped[0]], 1e-5),
                                    "flip {start:?} {end:?} {l} {r}"
                                );
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn offsets_shift_the_crossing_ends() {
        // A one-pixel run with a crossing on the current side, sample shifted by +1/4 towards
        // the pixel across and -1/4 along: the line starts at (-1/4, -1/4) and meets the edge
        // at (1/2, 0), so it enters the pixel at height -1/6: a triangle of 1/24.
        let a = ortho_area(Crossing::Current, Crossing::None, 0.0, 0.0, 0.25);
        assert!(close(a, [1.0 / 24.0, 0.0], 1e-6), "{a:?}");
        // A Z of length 3 with the same offset: the line from (-1/4, -1/4) to (11/4, 3/4)
        // crosses the middle pixel at heights 1/6 and 1/2, all of it across the edge.
        let z = ortho_area(Crossing::Current, Crossing::Opposite, 1.0, 1.0, 0.25);
        assert!(close(z, [0.0, (1.0 / 6.0 + 0.5) * 0.5], 1e-6), "{z:?}");
    }

    /// Exact area of pixel (px, py) on one side of the line, by fine numerical integration.
    fn integrated(line: &impl Fn(f64) -> f64, px: i32, py: i32, below: bool) -> f32 {
        let n = 400;
        let mut inside = 0usize;
        for i in 0..n {
            for j in 0..n {
                let x = f64::from(px) + (f64::from(i) + 0.5) / f64::from(n);
                let y = f64::from(py) + (f64::from(j) + 0.5) / f64::from(n);
                let f = line(x - y);
                if (below && x + y < f) || (!below && x + y > f) {
                    inside += 1;
                }
            }
        }
        inside as f32 / (n * n) as f32
    }

    #[test]
    fn diagonal_counting_equals_brute_force_sampling() {
        for (near, far, l, r, shift) in [
            (DiagonalEnd::Vertical, DiagonalEnd::Open, 0, 0, 0.0),
            (DiagonalEnd::Horizontal, DiagonalEnd::Vertical, 3, 1, 0.5),
            (DiagonalEnd::Vertical, DiagonalEnd::Vertical, 2, 5, -0.25),
            (DiagonalEnd::Open, DiagonalEnd::Horizontal, 7, 0, 0.25),
        ] {
            let line = diagonal_line(near, far, l, r, shift);
            for (px, py, below) in [(0, 0, true), (0, -1, false)] {
                let mut count = 0.0;
                for i in 0..DIAG_SAMPLES {
                    for j in 0..DIAG_SAMPLES {
                        let x = f64::from(px) + (f64::from(i) + 0.5) / 30.0;
                        let y = f64::from(py) + (f64::from(j) + 0.5) / 30.0;
                        let (v, f) = (x + y, line(x - y));
                        count += if (v - f).abs() < 1e-9 {
                            0.5
                        } else if (v < f) == below {
                            1.0
                        } else {
                            0.0
                        };
                    }
                }
                let fast = diagonal_coverage(&line, px, py, below);
                assert!(
                    (fast - count / 900.0).abs() < 1e-6,
                    "{near:?} {far:?} {l} {r}: {fast} vs {}",
                    count / 900.0
                );
            }
        }
    }

    #[test]
    fn diagonal_areas_match_hand_computation() {
        // An endless staircase: its line v = 1/2 cuts a corner triangle of 1/8 off both pixels,
        // exactly even with 30 x 30 samples because samples on the line count half.
        for (l, r) in [(0, 0), (5, 3), (19, 19)] {
            let a = diag_area(DiagonalEnd::Open, DiagonalEnd::Open, l, r, (0.0, 0.0));
            assert!(close(a, [0.125, 0.125], 1e-6), "{a:?}");
        }
        // Sample half a step towards the black side: the line runs through the pixel centre.
        let a = diag_area(DiagonalEnd::Open, DiagonalEnd::Open, 4, 4, (0.25, -0.25));
        assert!(close(a, [0.5, 0.0], 1e-6), "{a:?}");
        // An L ending in a vertical step at the current pixel: the line rises from (-1, 1)
        // to (0, 1/2) and stays there; by hand the current pixel has 3/16 and the pixel
        // above 1/8.
        let a = diag_area(DiagonalEnd::Vertical, DiagonalEnd::Open, 0, 0, (0.0, 0.0));
        assert!(close(a, [0.1875, 0.125], 1.0 / 60.0), "{a:?}");
        // Both ends step towards the black side (a U): the line bulges into the current
        // pixel and away from the pixel above.
        let a = diag_area(
            DiagonalEnd::Vertical,
            DiagonalEnd::Horizontal,
            3,
            3,
            (0.0, 0.0),
        );
        assert!(a[0] > 0.125 && a[1] < 0.125, "{a:?}");
    }

    #[test]
    fn diagonal_areas_are_close_to_exact_integration() {
        for near in DiagonalEnd::ALL {
            for far in DiagonalEnd::ALL {
                for (l, r) in [(0, 0), (1, 3), (6, 2), (19, 0)] {
                    for offset in DIAG_OFFSETS {
                        let shift = f64::from(offset.0 - offset.1);
                        let line = diagonal_line(near, far, l, r, shift);
                        let a = diag_area(near, far, l, r, offset);
                        let exact = [
                            integrated(&line, 0, 0, true),
                            integrated(&line, 0, -1, false),
                        ];
                        assert!(
                            close(a, exact, 0.02),
                            "{near:?} {far:?} {l} {r} {offset:?}: {a:?} vs {exact:?}"
                        );
                        assert!(a.iter().all(|v| (0.0..=1.0).contains(v)));
                    }
                }
            }
        }
    }

    #[test]
    fn every_diagonal_run_of_two_or_more_pixels_has_an_area() {
        // The weight pass tells whether a pixel's left neighbour blends along a `\` staircase
        // from the run's length alone (smaa.wgsl, `on_blended_staircase`): that holds only if
        // no run of two or more pixels reads a zero area, whatever its ends and sub-table.
        let t = tables();
        for sub in 0..DIAG_OFFSETS.len() as u32 {
            for (near, far) in (0..4u32).flat_map(|n| (0..4u32).map(move |f| (n, f))) {
                for (l, r) in (0..DIAG_CELL).flat_map(|l| (0..DIAG_CELL).map(move |r| (l, r))) {
                    if l + r < 2 {
                        continue;
                    }
                    let x = AREA_SIZE.0 / 2 + DIAG_CELL * near + l;
                    let y = sub * SUBTABLE_HEIGHT + DIAG_CELL * far + r;
                    let i = ((y * AREA_SIZE.0 + x) * 2) as usize;
                    assert!(
                        t.area[i] > 0 || t.area[i + 1] > 0,
                        "sub-table {sub}, ends {near}/{far}, lengths {l}/{r}: zero area"
                    );
                }
            }
        }
    }

    #[test]
    fn area_table_places_every_cell() {
        let t = tables();
        assert_eq!(t.area.len(), (AREA_SIZE.0 * AREA_SIZE.1 * 2) as usize);
        let texel = |x: u32, y: u32| {
            let i = ((y * AREA_SIZE.0 + x) * 2) as usize;
            [t.area[i], t.area[i + 1]]
        };
        // Orthogonal L, offset 0: start crossing on the current side (cell 3), 0 and 9 pixels.
        let expected = ortho_area(Crossing::Current, Crossing::None, 0.0, 9.0, 0.0).map(unorm8);
        assert_eq!(texel(3 * 16, 3), expected);
        // Offset 2 (+0.25), end crossing on the opposite side (cell 1), distances 4 and 1.
        let expected = ortho_area(Crossing::None, Crossing::Opposite, 4.0, 1.0, 0.25).map(unorm8);
        assert_eq!(texel(2, 2 * 80 + 16 + 1), expected);
        // Diagonal, sub-table 1, near end horizontal (2), far end vertical (1), 5 and 7.
        let expected = diag_area(
            DiagonalEnd::Horizontal,
            DiagonalEnd::Vertical,
            5,
            7,
            DIAG_OFFSETS[1],
        )
        .map(unorm8);
        assert_eq!(texel(80 + 40 + 5, 80 + 20 + 7), expected);
        // The unused cell column 2 of the orthogonal grid stays empty.
        assert_eq!(texel(2 * 16 + 5, 5), [0, 0]);
        // Flat runs are never filtered.
        for o in 0..7 {
            for i in 0..16 {
                assert_eq!(texel(i, o * 80 + 15 - i), [0, 0]);
            }
        }
    }

    #[test]
    fn search_fetch_values_decode_uniquely() {
        let valid: Vec<u32> = (0..=32).filter(|&i| decode_fetch(i).is_some()).collect();
        assert_eq!(
            valid,
            [0, 1, 3, 4, 7, 8, 10, 11, 21, 22, 24, 25, 28, 29, 31, 32]
        );
        assert_eq!(decode_fetch(28), Some([false, false, true, true]));
        assert_eq!(decode_fetch(2), None);
    }

    #[test]
    fn search_extra_lengths_match_hand_computation() {
        let none = [false; 4];
        let both = [false, false, true, true];
        let near_only = [false, false, false, true];
        assert_eq!(extra_backward(none, both), 2);
        assert_eq!(extra_backward(none, near_only), 1);
        assert_eq!(extra_backward(none, none), 0);
        // A crossing edge between near and far stops the backward run at the near pixel.
        assert_eq!(extra_backward([false, false, false, true], both), 1);
        // Beyond the far pixel it does not matter.
        assert_eq!(extra_backward([false, false, true, false], both), 2);
        // Forwards, a crossing edge before the near pixel ends the run before it.
        assert_eq!(extra_forward([false, true, false, false], both), 0);
        assert_eq!(extra_forward([true, false, false, false], both), 1);
        assert_eq!(extra_forward(none, both), 2);
    }

    #[test]
    fn search_table_keeps_every_nonzero_entry() {
        let t = tables();
        assert_eq!(t.search.len(), (SEARCH_SIZE.0 * SEARCH_SIZE.1) as usize);
        for c in 0..=32 {
            for e in 0..=32 {
                let (Some(crossing), Some(edge)) = (decode_fetch(c), decode_fetch(e)) else {
                    continue;
                };
                for forward in [false, true] {
                    let extra = if forward {
                        extra_forward(crossing, edge)
                    } else {
                        extra_backward(crossing, edge)
                    };
                    match search_texel(forward, c, e) {
                        Some((x, y)) => {
                            assert_eq!(
                                t.search[(y * SEARCH_SIZE.0 + x) as usize],
                                extra * SEARCH_UNIT
                            );
                        }
                        None => assert_eq!(extra, 0, "entry {c} {e} forward {forward} lost"),
                    }
                }
            }
        }
        assert!(
            t.search
                .iter()
                .all(|v| [0, SEARCH_UNIT, 2 * SEARCH_UNIT].contains(v))
        );
        // The run continuing through both pixels of a backward fetch: edge index 28, row 4.
        assert_eq!(t.search[(4 * SEARCH_SIZE.0) as usize], 2 * SEARCH_UNIT);
    }

    #[test]
    fn subsample_indices_follow_the_sample_position() {
        assert_eq!(subsample_indices(glam::Vec2::ZERO), [0, 0, 0, 0]);
        // Sample up and right of the centre: across a horizontal edge (towards the pixel
        // above) +1/4, across a vertical edge (towards the left pixel) -1/4, along the "/"
        // staircase, so no diagonal shift there, and half a step across "\" staircases.
        assert_eq!(
            subsample_indices(glam::Vec2::new(0.25, -0.25)),
            [2, 1, 0, 2]
        );
        assert_eq!(
            subsample_indices(glam::Vec2::new(-0.25, 0.25)),
            [1, 2, 0, 1]
        );
        // The standard 2x MSAA positions, relative to the centre.
        assert_eq!(subsample_indices(glam::Vec2::new(0.25, 0.25)), [1, 1, 1, 0]);
        assert_eq!(
            subsample_indices(glam::Vec2::new(-0.25, -0.25)),
            [2, 2, 2, 0]
        );
    }

    #[test]
    fn generation_is_fast() {
        let started = std::time::Instant::now();
        let area = area_table();
        let search = search_table();
        let elapsed = started.elapsed();
        assert!(!area.is_empty() && !search.is_empty());
        // Release builds take a few tens of milliseconds; allow for unoptimised test builds.
        assert!(elapsed.as_secs_f32() < 2.0, "generation took {elapsed:?}");
        println!(
            "SMAA lookup tables generated in {:.1} ms",
            elapsed.as_secs_f64() * 1e3
        );
    }
}
