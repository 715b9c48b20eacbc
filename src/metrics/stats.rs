//! Summaries of repeated measurements (GPU milliseconds over many frames): median and 95th
//! percentile by linear interpolation between order statistics (NumPy's default), plus mean,
//! minimum and maximum.

/// Summary of a set of samples.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Summary {
    /// Number of samples.
    pub count: usize,
    /// Median.
    pub median: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Arithmetic mean.
    pub mean: f64,
    /// Smallest sample.
    pub min: f64,
    /// Largest sample.
    pub max: f64,
}

/// The `q` quantile (0..=1) of ascending `sorted` samples, linearly interpolated; 0 when empty.
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    match sorted.len() {
        0 => 0.0,
        1 => sorted[0],
        n => {
            let position = q.clamp(0.0, 1.0) * (n - 1) as f64;
            let below = position.floor() as usize;
            let above = (below + 1).min(n - 1);
            let t = position - below as f64;
            sorted[below] + (sorted[above] - sorted[below]) * t
        }
    }
}

impl Summary {
    /// Summarises samples (any order; non-finite samples are dropped).
    pub fn of(samples: &[f64]) -> Self {
        let mut sorted: Vec<f64> = samples.iter().copied().filter(|v| v.is_finite()).collect();
        sorted.sort_by(f64::total_cmp);
        let count = sorted.len();
        if count == 0 {
            return Self::default();
        }
        Self {
            count,
            median: quantile(&sorted, 0.5),
            p95: quantile(&sorted, 0.95),
            mean: sorted.iter().sum::<f64>() / count as f64,
            min: sorted[0],
            max: sorted[count - 1],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate_like_numpy() {
        let s = Summary::of(&[4.0, 1.0, 3.0, 2.0]);
        assert_eq!(s.median, 2.5);
        assert!((s.p95 - 3.85).abs() < 1e-12);
        assert_eq!((s.min, s.max, s.mean, s.count), (1.0, 4.0, 2.5, 4));
        assert_eq!(Summary::of(&[7.0]).p95, 7.0);
        assert_eq!(Summary::of(&[]).count, 0);
        assert_eq!(Summary::of(&[f64::NAN, 2.0]).median, 2.0);
    }
}
