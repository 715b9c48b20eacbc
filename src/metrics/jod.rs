//! ColorVideoVDP (Mantiuk, Hanji, Ashraf, Asano and Chapiro, "ColorVideoVDP: A visual difference
//! predictor for image, video and display distortions", SIGGRAPH 2024): how visible the
//! difference between a test clip and its reference is to a person watching it on a given
//! display, in JOD units (10: no visible difference; one JOD apart, 75 % of observers prefer the
//! higher-scoring clip). Unlike SSIM, PSNR and FLIP, which score one frame at a time, it models
//! the eye's temporal channels, so a technique that flickers or crawls scores lower than its
//! per-frame error alone says: the calibrated counterpart of aa-lab's own instability figure.
//!
//! The model is the pure-Rust port `colorvideovdp` (MIT, calibrated base model v0.5.7, which its
//! authors check against the reference PyTorch implementation `cvvdp`); this file only hands it
//! aa-lab's frames: sRGB-encoded 8-bit RGBA, alpha dropped, as `Color::Srgb` on the chosen
//! display model ([`JodScorer::new`]: the reference's standard displays by name, e.g.
//! `standard_fhd`, a 24-inch 1920x1080 200 cd/m² monitor seen from 0.6 m under office light,
//! [`DEFAULT_DISPLAY`]). A clip is scored as a video at its playback rate; one frame as an image.
//!
//! **Viewing distance.** The model sees the display's geometry only as pixels per degree of
//! visual angle (`colorvideovdp::Geometry`: once a standard display is loaded it keeps its
//! resolution and pixels per degree, not its diagonal or distance), so a nearer or farther
//! viewer is given as pixels per degree replacing the model's ([`JodDisplay`]: twice the
//! distance is about twice the pixels per degree). Records state the pixels per degree used,
//! overridden or not, so a replay scores on the same geometry.
//!
//! Cost: the model keeps each clip's frames as 32-bit floats (12 bytes a pixel, so a 48-frame
//! 1280x720 clip and its reference take about 1 GB together) and works on every core.

use std::borrow::Borrow;

use colorvideovdp::{Color, Cvvdp, DisplayModel, Geometry, Image, Options};

use super::{MetricsError, Plane};

/// The display model clips are scored for unless one is named.
pub const DEFAULT_DISPLAY: &str = "standard_fhd";

/// The ColorVideoVDP version of the calibrated model.
pub const MODEL_VERSION: &str = Cvvdp::MODEL_VERSION;

/// The most pixels per degree a viewing distance may give (a 4K display seen from about 16
/// times its height); the standard display models have 25 (a zoomed HDR view) to 121 (a
/// phone).
pub const MAX_PIXELS_PER_DEGREE: f64 = 600.0;

/// The display a JOD is predicted for: one of ColorVideoVDP's standard display models by name,
/// and optionally the pixels per degree of visual angle replacing the model's (a viewer nearer
/// or farther than the model's; see the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct JodDisplay {
    /// The display model's name (see [`JodScorer::displays`]).
    pub name: String,
    /// Pixels per degree replacing the model's (`None`: the model's own).
    pub pixels_per_degree: Option<f64>,
}

impl JodDisplay {
    /// The standard display `name` at its own viewing distance.
    pub fn named(name: &str) -> Self {
        Self {
            name: name.to_owned(),
            pixels_per_degree: None,
        }
    }

    /// A short description for labels: the name, and the pixels per degree when replaced.
    pub fn describe(&self) -> String {
        match self.pixels_per_degree {
            Some(ppd) => format!("{} at {ppd:.1} px/deg", self.name),
            None => self.name.clone(),
        }
    }
}

impl Default for JodDisplay {
    fn default() -> Self {
        Self::named(DEFAULT_DISPLAY)
    }
}

/// Most bytes a scoring may hold: every frame of a test and of its reference as 8-bit pixels
/// and as the model's floats (16 bytes a pixel and frame in all).
pub const MAX_SCORED_BYTES: u64 = 8 << 30;

/// Checks that scoring `frames` frames of `size` stays within [`MAX_SCORED_BYTES`].
pub fn check_memory(size: (u32, u32), frames: usize) -> Result<(), MetricsError> {
    let bytes = u64::from(size.0) * u64::from(size.1) * 16 * frames as u64;
    if bytes <= MAX_SCORED_BYTES {
        return Ok(());
    }
    Err(MetricsError::Jod(format!(
        "scoring holds every frame of the test and the reference: {frames} frames of {}x{} take \
         {} GiB, more than the {} GiB allowed; score fewer frames",
        size.0,
        size.1,
        bytes >> 30,
        MAX_SCORED_BYTES >> 30
    )))
}

/// Checks pixels per degree given for a viewing distance: finite, above 0 and at most
/// [`MAX_PIXELS_PER_DEGREE`].
pub fn check_pixels_per_degree(ppd: f64) -> Result<f64, MetricsError> {
    if ppd.is_finite() && ppd > 0.0 && ppd <= MAX_PIXELS_PER_DEGREE {
        Ok(ppd)
    } else {
        Err(MetricsError::Jod(format!(
            "pixels per degree must be above 0 and at most {MAX_PIXELS_PER_DEGREE}, not {ppd}"
        )))
    }
}

/// How JOD figures were computed, as records state it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct JodSetting {
    /// The display model, by its ColorVideoVDP name.
    pub display: String,
    /// The pixels per degree the model saw: the display model's own or the one given.
    pub pixels_per_degree: f64,
    /// Whether `pixels_per_degree` replaced the display model's (a viewing distance given).
    pub pixels_per_degree_given: bool,
    /// The model's calibration version.
    pub model: &'static str,
    /// The frame rate the clips were played at.
    pub fps: f32,
}

/// Scores clips against their reference on one display model.
pub struct JodScorer {
    metric: Cvvdp,
    display: JodDisplay,
    /// Whether predictions keep the per-pixel distortion map ([`JodScorer::score_with_map`]).
    mapped: bool,
}

fn error(err: colorvideovdp::Error) -> MetricsError {
    MetricsError::Jod(err.to_string())
}

impl JodScorer {
    /// A scorer for the standard display model `display` at its own viewing distance (see
    /// [`JodScorer::displays`]).
    pub fn new(display: &str) -> Result<Self, MetricsError> {
        Self::for_display(&JodDisplay::named(display), false)
    }

    /// [`JodScorer::new`] whose scores also give the per-pixel distortion map (it costs one
    /// more plane per frame while scoring).
    pub fn with_distortion_map(display: &str) -> Result<Self, MetricsError> {
        Self::for_display(&JodDisplay::named(display), true)
    }

    /// A scorer for `display` (a standard model, its pixels per degree replaced when given);
    /// `mapped`: its scores also give the distortion map ([`JodScorer::score_with_map`]).
    pub fn for_display(display: &JodDisplay, mapped: bool) -> Result<Self, MetricsError> {
        let mut model = DisplayModel::from_name(&display.name).map_err(|err| {
            MetricsError::Jod(format!(
                "{err}; display models: {}",
                Self::displays().join(", ")
            ))
        })?;
        if let Some(ppd) = display.pixels_per_degree {
            let ppd = check_pixels_per_degree(ppd)?;
            model.geometry = Geometry::from_ppd(model.geometry.resolution(), ppd).map_err(error)?;
        }
        let options = Options::default().with_distortion_map(mapped);
        Ok(Self {
            metric: Cvvdp::new(model, options).map_err(error)?,
            display: display.clone(),
            mapped,
        })
    }

    /// Whether its scores give the distortion map.
    pub fn mapped(&self) -> bool {
        self.mapped
    }

    /// The pixels per degree of the standard display `name` at its own viewing distance.
    pub fn model_pixels_per_degree(name: &str) -> Option<f64> {
        let model = DisplayModel::from_name(name).ok()?;
        Some(model.geometry.pixels_per_degree())
    }

    /// The names of the display models the model ships with.
    pub fn displays() -> Vec<&'static str> {
        DisplayModel::names().unwrap_or_default()
    }

    /// The display it scores for.
    pub fn display(&self) -> &JodDisplay {
        &self.display
    }

    /// The pixels per degree the model sees (the display model's own or the one given).
    pub fn pixels_per_degree(&self) -> f64 {
        self.metric.display().geometry.pixels_per_degree()
    }

    /// What a record says of figures this scorer gives at `fps`.
    pub fn setting(&self, fps: f32) -> JodSetting {
        JodSetting {
            display: self.display.name.clone(),
            pixels_per_degree: self.pixels_per_degree(),
            pixels_per_degree_given: self.display.pixels_per_degree.is_some(),
            model: MODEL_VERSION,
            fps,
        }
    }

    /// The JOD of each of `tests` (every technique's frames, in order) against the same
    /// `reference`, played at `fps`; `starting(i)` is called before clip `i` is scored (each
    /// takes seconds), so a front end can say which.
    pub fn score_each<T, R>(
        &self,
        tests: &[Vec<T>],
        reference: &[R],
        fps: f32,
        mut starting: impl FnMut(usize),
    ) -> Result<Vec<f64>, MetricsError>
    where
        T: Borrow<image::RgbaImage>,
        R: Borrow<image::RgbaImage>,
    {
        tests
            .iter()
            .enumerate()
            .map(|(i, test)| {
                starting(i);
                self.score(test, reference, fps)
            })
            .collect()
    }

    /// The JOD of `test` against `reference`, frame by frame in order, played at `fps`
    /// frames per second (a single frame is scored as an image).
    pub fn score<T, R>(&self, test: &[T], reference: &[R], fps: f32) -> Result<f64, MetricsError>
    where
        T: Borrow<image::RgbaImage>,
        R: Borrow<image::RgbaImage>,
    {
        Ok(f64::from(self.predict(test, reference, fps)?.jod))
    }

    /// [`JodScorer::score`] with the per-pixel distortion map averaged over the frames: each
    /// value is `1 - JOD / 10` of that pixel (0: no visible difference; the model does not
    /// clip it). Only a scorer made [`JodScorer::with_distortion_map`] has the map.
    pub fn score_with_map<T, R>(
        &self,
        test: &[T],
        reference: &[R],
        fps: f32,
    ) -> Result<(f64, Plane), MetricsError>
    where
        T: Borrow<image::RgbaImage>,
        R: Borrow<image::RgbaImage>,
    {
        if !self.mapped {
            return Err(MetricsError::Jod(
                "this scorer was made without the distortion map".to_owned(),
            ));
        }
        let prediction = self.predict(test, reference, fps)?;
        let map = prediction
            .distortion_map
            .ok_or_else(|| MetricsError::Jod("the model returned no distortion map".to_owned()))?;
        let pixels = map.width * map.height;
        let mut mean = vec![0.0f32; pixels];
        for frame in map.data.chunks_exact(pixels) {
            mean.iter_mut().zip(frame).for_each(|(m, v)| *m += v);
        }
        let frames = map.frames.max(1) as f32;
        mean.iter_mut().for_each(|m| *m /= frames);
        let plane = Plane {
            width: map.width as u32,
            height: map.height as u32,
            data: mean,
        };
        Ok((f64::from(prediction.jod), plane))
    }

    /// The model's prediction for `test` against `reference` (see [`JodScorer::score`]).
    fn predict<T, R>(
        &self,
        test: &[T],
        reference: &[R],
        fps: f32,
    ) -> Result<colorvideovdp::Prediction, MetricsError>
    where
        T: Borrow<image::RgbaImage>,
        R: Borrow<image::RgbaImage>,
    {
        if test.len() != reference.len() {
            return Err(MetricsError::FrameCount {
                expected: reference.len(),
                got: test.len(),
            });
        }
        for (t, r) in test.iter().zip(reference) {
            let (t, r) = (t.borrow(), r.borrow());
            if t.dimensions() != r.dimensions() {
                return Err(MetricsError::SizeMismatch {
                    reference: r.dimensions(),
                    test: t.dimensions(),
                });
            }
        }
        let test: Vec<Image> = test
            .iter()
            .map(|i| linear_input(i.borrow()))
            .collect::<Result<_, _>>()?;
        let reference: Vec<Image> = reference
            .iter()
            .map(|i| linear_input(i.borrow()))
            .collect::<Result<_, _>>()?;
        let prediction = match test.len() {
            1 => self
                .metric
                .predict_image(&test[0], &reference[0], Color::Srgb),
            _ => self
                .metric
                .predict_video(&test, &reference, fps, Color::Srgb),
        }
        .map_err(error)?;
        Ok(prediction)
    }
}

/// An RGBA8 frame as the model's interleaved RGB floats in [0, 1] (still sRGB-encoded).
fn linear_input(rgba: &image::RgbaImage) -> Result<Image, MetricsError> {
    let data = rgba
        .pixels()
        .flat_map(|p| [p[0], p[1], p[2]])
        .map(|v| f32::from(v) / 255.0)
        .collect();
    Image::new(rgba.width() as usize, rgba.height() as usize, 3, data).map_err(error)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(width: u32, height: u32, seed: u32, amplitude: i32) -> image::RgbaImage {
        image::RgbaImage::from_fn(width, height, |x, y| {
            let base = ((x * 7 + y * 3) % 64) as i32 + 96;
            let h =
                (x.wrapping_mul(73856093) ^ y.wrapping_mul(19349663) ^ seed.wrapping_mul(83492791))
                    % 1000;
            let v = (base + (h as i32 % (2 * amplitude + 1)) - amplitude).clamp(0, 255) as u8;
            image::Rgba([v, v, v, 255])
        })
    }

    /// `image` with every channel raised by `delta` levels.
    fn brighter(image: &image::RgbaImage, delta: i32) -> image::RgbaImage {
        let mut out = image.clone();
        for p in out.pixels_mut() {
            for c in &mut p.0[..3] {
                *c = (i32::from(*c) + delta).clamp(0, 255) as u8;
            }
        }
        out
    }

    #[test]
    fn the_distortion_map_is_hot_where_the_test_differs_and_only_with_a_mapping_scorer() {
        let reference: Vec<_> = (0..4).map(|_| noise(128, 64, 0, 0)).collect();
        // Noise on the left quarter of every test frame, different in each frame.
        let test: Vec<_> = (0..4)
            .map(|seed| {
                let noisy = noise(128, 64, seed + 1, 40);
                let mut out = reference[0].clone();
                for (x, y, p) in out.enumerate_pixels_mut() {
                    if x < 32 {
                        *p = *noisy.get_pixel(x, y);
                    }
                }
                out
            })
            .collect();
        let mapping = JodScorer::with_distortion_map(DEFAULT_DISPLAY).expect("scorer");
        let (jod, map) = mapping
            .score_with_map(&test, &reference, 30.0)
            .expect("score");
        assert_eq!((map.width, map.height), (128, 64));
        let plain = JodScorer::new(DEFAULT_DISPLAY).expect("scorer");
        let plain_jod = plain.score(&test, &reference, 30.0).expect("score");
        assert!((jod - plain_jod).abs() < 1e-3, "{jod} vs {plain_jod}");
        let mean = |xs: std::ops::Range<u32>| {
            let values: Vec<f32> = (0..64)
                .flat_map(|y| xs.clone().map(move |x| (x, y)))
                .map(|(x, y)| map.data[(y * 128 + x) as usize])
                .collect();
            values.iter().sum::<f32>() / values.len() as f32
        };
        let (noisy, clean) = (mean(0..24), mean(96..128));
        assert!(
            noisy > 2.0 * clean,
            "noisy quarter {noisy}, clean quarter {clean}"
        );
        assert!(plain.score_with_map(&test, &reference, 30.0).is_err());
    }

    #[test]
    fn identical_clips_score_ten_and_flicker_scores_lower_than_a_steady_error() {
        let scorer = JodScorer::new(DEFAULT_DISPLAY).expect("standard display");
        let reference: Vec<_> = (0..8).map(|_| noise(64, 48, 0, 0)).collect();
        let same = scorer.score(&reference, &reference, 30.0).expect("score");
        assert!((same - 10.0).abs() < 1e-3, "identical clips: {same}");
        // The same brightness error on every frame, and one that alternates in sign (a 15 Hz
        // flicker of the same size): the eye sees the flicker far more.
        let steady: Vec<_> = reference.iter().map(|f| brighter(f, 8)).collect();
        let flicker: Vec<_> = reference
            .iter()
            .enumerate()
            .map(|(i, f)| brighter(f, if i % 2 == 0 { 8 } else { -8 }))
            .collect();
        let steady = scorer.score(&steady, &reference, 30.0).expect("score");
        let flicker = scorer.score(&flicker, &reference, 30.0).expect("score");
        assert!(steady < 10.0, "a visible error: {steady}");
        assert!(
            flicker < steady - 0.5,
            "flicker {flicker} should score well below the steady error {steady}"
        );
    }

    #[test]
    fn a_nearer_viewer_sees_more_of_the_error_and_the_setting_says_so() {
        let reference: Vec<_> = (0..4).map(|_| noise(96, 64, 0, 0)).collect();
        let test: Vec<_> = (0..4).map(|seed| noise(96, 64, seed + 1, 12)).collect();
        let standard = JodScorer::new(DEFAULT_DISPLAY).expect("display");
        let own = standard.pixels_per_degree();
        let score = |ppd: f64| {
            let display = JodDisplay {
                name: DEFAULT_DISPLAY.to_owned(),
                pixels_per_degree: Some(ppd),
            };
            let scorer = JodScorer::for_display(&display, false).expect("display");
            let setting = scorer.setting(30.0);
            assert_eq!(setting.pixels_per_degree, ppd);
            assert!(setting.pixels_per_degree_given);
            scorer.score(&test, &reference, 30.0).expect("score")
        };
        // Fine noise is masked for a viewer far away (many pixels per degree) and plain to
        // one close up.
        let (near, far) = (score(own / 3.0), score(own * 3.0));
        assert!(near < far - 0.2, "near {near}, far {far}");
        let setting = standard.setting(30.0);
        assert!(!setting.pixels_per_degree_given && (20.0..100.0).contains(&own));
        for bad in [0.0, -3.0, f64::NAN, MAX_PIXELS_PER_DEGREE + 1.0] {
            let display = JodDisplay {
                name: DEFAULT_DISPLAY.to_owned(),
                pixels_per_degree: Some(bad),
            };
            assert!(JodScorer::for_display(&display, false).is_err(), "{bad}");
        }
    }

    #[test]
    fn unknown_displays_and_mismatched_clips_are_refused_clearly() {
        let err = JodScorer::new("crt_1995")
            .err()
            .expect("refused")
            .to_string();
        assert!(err.contains("standard_fhd"), "{err}");
        let scorer = JodScorer::new(DEFAULT_DISPLAY).expect("display");
        let a = [noise(16, 16, 0, 0)];
        let b = [noise(16, 16, 0, 0), noise(16, 16, 0, 0)];
        assert!(matches!(
            scorer.score(&a, &b, 30.0),
            Err(MetricsError::FrameCount { .. })
        ));
        let c = [noise(8, 16, 0, 0)];
        assert!(matches!(
            scorer.score(&c, &a, 30.0),
            Err(MetricsError::SizeMismatch { .. })
        ));
    }
}
