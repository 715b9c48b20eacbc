//! MLAA's area table, generated here from the pattern geometry once per process and cached.
//!
//! For a pixel on an edge run found by the blending-weight pass, the table answers how much of
//! the pixel the colour across the edge covers (channel 0) and how much of the pixel across
//! the edge this pixel's colour covers (channel 1), given the distances to the run's two ends
//! and the crossing edges found there.
//!
//! The geometry is Reshetov's: along the run, x goes from 0 at the start of its first pixel to
//! `d = left + right + 1` at the end of its last, and the current pixel covers
//! `[left, left + 1]`; y = 0 is the edge, negative y lies in the current pixel's row. A
//! crossing edge at an end is half a pixel long on the side where it lies, so the outline is
//! rebuilt through its middle, height -1/2 (current side) or +1/2 (opposite side). Every
//! pattern is made of L shapes that meet the edge in the middle of the run, `(d/2, 0)`:
//! - L (one end crossed): from that end to the middle; the other half is left alone;
//! - Z (both ends, opposite sides): the two halves form one straight line end to end;
//! - U (both ends, same side): two L shapes meeting in the middle.
//!
//! An end without a crossing edge, or with crossings on both sides (a junction, which MLAA has
//! no rule for), bends nothing, so pixel-aligned edges and junctions stay sharp. The area
//! between the line and the edge over the current pixel is integrated exactly. Unlike SMAA's
//! table there is no rounding of short U shapes, no sub-sample offsets and no diagonal part,
//! and distances are stored linearly.
//!
//! # Layout (165 x 165, two channels)
//! A 5 x 5 grid of cells, cell `(start, end)` at [`Crossing::cell`] (`3 * current +
//! opposite`, which is what the shader's bilinear fetch a quarter pixel across the edge reads
//! times four); inside a cell, texel `(left, right)` holds the distances themselves, 0 to
//! [`MAX_DISTANCE`].

use std::sync::OnceLock;

use crate::aa::common::morphology::{Crossing, polyline_area};

/// The longest distance to a run end the table holds (the search reads at most this far).
pub const MAX_DISTANCE: u32 = 32;
/// Side of one cell: distances 0..=[`MAX_DISTANCE`].
pub const CELL: u32 = MAX_DISTANCE + 1;
/// Size of the table in texels.
pub const AREA_SIZE: (u32, u32) = (5 * CELL, 5 * CELL);

/// Areas (current pixel, pixel across the edge) for a run reaching `left` pixels before and
/// `right` pixels after the current one, with the given crossing edges at its start and end
/// (module docs).
pub fn area(start: Crossing, end: Crossing, left: u32, right: u32) -> [f32; 2] {
    let (left, right) = (left as f32, right as f32);
    let d = left + right + 1.0;
    let middle = (0.5 * d, 0.0);
    let points = match (start.height(0.0), end.height(0.0)) {
        (None, None) => return [0.0, 0.0],
        (Some(y), None) => vec![(0.0, y), middle],
        (None, Some(y)) => vec![middle, (d, y)],
        // A Z's two halves are one line; a U's meet on the edge.
        (Some(y0), Some(y1)) => vec![(0.0, y0), middle, (d, y1)],
    };
    polyline_area(&points, left, left + 1.0)
}

/// The table, two bytes per texel (Rg8Unorm), rows packed; generated on first use.
pub fn table() -> &'static [u8] {
    static TABLE: OnceLock<Vec<u8>> = OnceLock::new();
    TABLE.get_or_init(|| {
        let (width, height) = AREA_SIZE;
        let mut data = vec![0u8; (width * height * 2) as usize];
        for start in Crossing::ALL {
            for end in Crossing::ALL {
                for left in 0..CELL {
                    for right in 0..CELL {
                        let x = start.cell() * CELL + left;
                        let y = end.cell() * CELL + right;
                        let i = ((y * width + x) * 2) as usize;
                        let a = area(start, end, left, right);
                        data[i] = unorm8(a[0]);
                        data[i + 1] = unorm8(a[1]);
                    }
                }
            }
        }
        data
    })
}

fn unorm8(x: f32) -> u8 {
    (x.clamp(0.0, 1.0) * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f32; 2], b: [f32; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-6 && (a[1] - b[1]).abs() < 1e-6
    }

    #[test]
    fn l_shapes_match_hand_computation() {
        // Run of 4 with a crossing on the current side at the start: the line falls from
        // (0, -1/2) to (2, 0); pixel 0 is a trapezoid of heights 1/2 and 1/4, pixel 1 a
        // triangle, the second half untouched.
        let l = |left| area(Crossing::Current, Crossing::None, left, 3 - left);
        assert!(close(l(0), [0.375, 0.0]));
        assert!(close(l(1), [0.125, 0.0]));
        assert!(close(l(2), [0.0, 0.0]));
        assert!(close(l(3), [0.0, 0.0]));
        // The same on the opposite side goes into the other channel.
        assert!(close(
            area(Crossing::Opposite, Crossing::None, 0, 3),
            [0.0, 0.375]
        ));
        // Run of six: the line falls by 1/6 per pixel, so pixel 0 averages 5/12 and pixel 2
        // (the last of the first half) 1/12.
        let six = |left| area(Crossing::Current, Crossing::None, left, 5 - left)[0];
        assert!((six(0) - 5.0 / 12.0).abs() < 1e-6);
        assert!((six(2) - 1.0 / 12.0).abs() < 1e-6);
    }

    #[test]
    fn z_and_u_shapes_split_at_the_middle() {
        // One-pixel Z: the line crosses the edge at the pixel's centre, an eighth each side.
        assert!(close(
            area(Crossing::Current, Crossing::Opposite, 0, 0),
            [0.125, 0.125]
        ));
        // One-pixel U: both halves dip into the current pixel, a quarter in all.
        assert!(close(
            area(Crossing::Current, Crossing::Current, 0, 0),
            [0.25, 0.0]
        ));
        // A long Z is a straight line: the areas of its pixels add up to two triangles of
        // height 1/2 over half the run each.
        let d = 9;
        let total = (0..d)
            .map(|left| area(Crossing::Current, Crossing::Opposite, left, d - 1 - left))
            .fold([0.0, 0.0], |s, a| [s[0] + a[0], s[1] + a[1]]);
        assert!(close(total, [d as f32 / 8.0, d as f32 / 8.0]), "{total:?}");
    }

    #[test]
    fn flat_ends_and_junctions_bend_nothing_and_mirroring_is_symmetric() {
        for start in Crossing::ALL {
            for end in Crossing::ALL {
                for (left, right) in [(0, 0), (3, 7), (32, 5)] {
                    let a = area(start, end, left, right);
                    assert!(close(a, area(end, start, right, left)), "{start:?} {end:?}");
                    let flat = |c| matches!(c, Crossing::None | Crossing::Both);
                    if flat(start) && flat(end) {
                        assert_eq!(a, [0.0, 0.0]);
                    }
                    assert!(a[0] <= 0.5 && a[1] <= 0.5, "{a:?}");
                }
            }
        }
    }

    #[test]
    fn table_cells_follow_the_shaders_crossing_code() {
        let t = table();
        assert_eq!(t.len(), (AREA_SIZE.0 * AREA_SIZE.1 * 2) as usize);
        // Start crossed on the current side (code 3), end flat (0), left 0, right 3.
        let (x, y) = (3 * CELL, 0);
        let i = ((y * AREA_SIZE.0 + x) * 2 + 3 * AREA_SIZE.0 * 2) as usize;
        assert_eq!((t[i], t[i + 1]), (unorm8(0.375), 0));
        // Opposite-side start (code 1) lands in the second channel.
        let i = ((CELL + 3 * AREA_SIZE.0) * 2) as usize;
        assert_eq!((t[i], t[i + 1]), (0, unorm8(0.375)));
    }
}
