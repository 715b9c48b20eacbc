//! Where SSAA's samples go: how an ordered-grid render is cut into tiles that stay within
//! the adapter's texture limits ([`TilePlan`]), and the order in which a progressive
//! accumulation takes a pattern's samples so that every prefix is spread over the pixel
//! ([`progressive_order`]).

use glam::{UVec2, Vec2};

use crate::scene::camera::PixelRect;

/// The largest tile side (in supersampled pixels) rendered at once on a GPU: a 4096-pixel
/// tile's colour and depth take 200 MB of video memory, and fewer tiles mean less vertex work.
pub const MAX_TILE_SIDE: u32 = 4096;

/// The largest tile side on a software adapter, whose textures are the process's own memory:
/// a 2048-pixel tile's colour and depth take 50 MB (a 1280x720 reference at 8 x 8 renders in 15
/// tiles instead of 6, and its peak memory falls by about 50 MB).
pub const SOFTWARE_MAX_TILE_SIDE: u32 = 2048;

/// How an ordered-grid image is cut into tiles: output-pixel tiles of `tile` size.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TilePlan {
    /// Output image size.
    pub size: UVec2,
    /// Output pixels per tile (the last row/column may be cut by the image edge).
    pub tile: UVec2,
    /// Factor k.
    pub factor: u32,
}

impl TilePlan {
    /// Plans tiles whose supersampled side stays within `max_side`.
    pub fn new(size: (u32, u32), factor: u32, max_side: u32) -> Self {
        let per_axis = |extent: u32| {
            // The fewest tiles whose supersampled side fits; rounding the tile size up can
            // overshoot, so add tiles until it does not (a tile is at least one pixel).
            let mut count = (extent * factor).div_ceil(max_side).max(1);
            while count < extent && extent.div_ceil(count) * factor > max_side {
                count += 1;
            }
            extent.div_ceil(count)
        };
        Self {
            size: UVec2::new(size.0, size.1),
            tile: UVec2::new(per_axis(size.0), per_axis(size.1)),
            factor,
        }
    }

    /// Every tile as an output-pixel rectangle, clipped to the image.
    pub fn tiles(&self) -> Vec<PixelRect> {
        let mut out = Vec::new();
        let mut y = 0;
        while y < self.size.y {
            let mut x = 0;
            while x < self.size.x {
                out.push(PixelRect {
                    x,
                    y,
                    width: self.tile.x.min(self.size.x - x),
                    height: self.tile.y.min(self.size.y - y),
                });
                x += self.tile.x;
            }
            y += self.tile.y;
        }
        out
    }
}

/// Reorders sample positions so that every prefix is spread over the pixel: each next sample
/// is the one farthest (on the wrapping unit square) from those already taken, ties going to
/// the earlier index. Deterministic, O(n^2) for the at most 256 samples of a pattern.
pub fn progressive_order(positions: &[Vec2]) -> Vec<Vec2> {
    let wrapped = |a: Vec2, b: Vec2| {
        let d = (a - b).abs();
        d.min(Vec2::ONE - d).length_squared()
    };
    let mut left: Vec<Vec2> = positions.to_vec();
    let mut out = Vec::with_capacity(left.len());
    let mut nearest = vec![f32::INFINITY; left.len()];
    while !left.is_empty() {
        let next = nearest
            .iter()
            .enumerate()
            .fold(0, |best, (i, d)| if *d > nearest[best] { i } else { best });
        let taken = left.remove(next);
        nearest.remove(next);
        for (n, p) in nearest.iter_mut().zip(&left) {
            *n = n.min(wrapped(*p, taken));
        }
        out.push(taken);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::common::sampling::Pattern;

    #[test]
    fn tiles_cover_the_image_exactly_once() {
        for (size, factor, side) in [
            ((1280, 720), 8, 4096),
            ((3840, 2160), 8, 4096),
            ((7, 5), 3, 8),
            ((100, 100), 1, 4096),
        ] {
            let plan = TilePlan::new(size, factor, side);
            assert!(
                plan.tile.x * factor <= side && plan.tile.y * factor <= side,
                "{plan:?}"
            );
            let area: u32 = plan.tiles().iter().map(|t| t.width * t.height).sum();
            assert_eq!(area, size.0 * size.1);
            assert!(
                plan.tiles()
                    .iter()
                    .all(|t| t.x + t.width <= size.0 && t.y + t.height <= size.1)
            );
        }
    }

    #[test]
    fn progressive_order_is_a_permutation_with_spread_prefixes() {
        let grid = Pattern::Grid.positions(64);
        let ordered = progressive_order(&grid);
        let key = |p: &Vec2| ((p.x * 16.0) as u32, (p.y * 16.0) as u32);
        let mut a: Vec<_> = grid.iter().map(key).collect();
        let mut b: Vec<_> = ordered.iter().map(key).collect();
        a.sort_unstable();
        b.sort_unstable();
        assert_eq!(a, b);
        // The first four samples fall in four different quadrants of the pixel.
        let mut quadrants: Vec<_> = ordered[..4]
            .iter()
            .map(|p| (p.x >= 0.5, p.y >= 0.5))
            .collect();
        quadrants.sort_unstable();
        quadrants.dedup();
        assert_eq!(quadrants.len(), 4, "{:?}", &ordered[..4]);
        // The first 16 samples are one per 4x4 cell.
        let mut cells: Vec<_> = ordered[..16]
            .iter()
            .map(|p| ((p.x * 4.0) as u32, (p.y * 4.0) as u32))
            .collect();
        cells.sort_unstable();
        cells.dedup();
        assert_eq!(cells.len(), 16);
        assert_eq!(progressive_order(&[]), Vec::<Vec2>::new());
    }
}
