//! MSAA's settings beyond the sample count: how the samples are resolved into pixels.

use crate::aa::common::sampling::Filter;

crate::named_enum! {
    /// How samples become pixels (the `resolve` parameter).
    pub enum Resolve {
        /// The hardware average of the pixel's own samples.
        Box => "box",
        /// A tent filter over the samples of the pixel and its neighbours, in linear light.
        Tent => "tent",
        /// A Gaussian over the samples of the pixel and its neighbours, in linear light.
        Gaussian => "gaussian",
        /// A Blackman-Harris window over the samples of the pixel and its neighbours.
        BlackmanHarris => "blackman-harris",
        /// Half the pixel's own samples and an eighth of each corner (like NVIDIA's Quincunx).
        Quincunx => "quincunx",
    }
}

impl Resolve {
    /// The reconstruction filter of a filtered resolve (`None` for quincunx).
    pub fn filter(self) -> Option<Filter> {
        match self {
            Self::Box => Some(Filter::Box),
            Self::Tent => Some(Filter::Tent),
            Self::Gaussian => Some(Filter::Gaussian),
            Self::BlackmanHarris => Some(Filter::BlackmanHarris),
            Self::Quincunx => None,
        }
    }
}
