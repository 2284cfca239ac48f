//! How long each stage of a denoise took, and the quality OIDN says each
//! of its filters ran at: what `cargo xtask bench --only denoise`
//! sets beside `oidnBenchmark`'s own figures (the issue asks for at most
//! 1.1 times OIDN's time).

use super::Quality;

/// One run of an OIDN filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterRun {
    /// The quality the filter had when it ran, read back from OIDN (None
    /// for a value OIDN 2.5 does not name).
    pub quality: Option<Quality>,
    /// `oidnCommitFilter`: OIDN reads its parameters.
    pub commit_seconds: f64,
    /// `oidnExecuteFilter`: the network, built on the first execution
    /// (its weights laid out, its working memory taken), then run.
    pub execute_seconds: f64,
}

impl FilterRun {
    pub fn seconds(&self) -> f64 {
        self.commit_seconds + self.execute_seconds
    }
}

/// The stages of one denoise, in order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stages {
    /// OIDN's CPU device made (and the library loaded, the first time).
    pub device_seconds: f64,
    /// Our own pass over the pixels before OIDN: what is not a finite
    /// number made 0, the light seen directly taken out of the colour, the
    /// guides copied (they are prefiltered in place and kept as rendered).
    pub prepare_seconds: f64,
    /// The prefilters of the albedo and the normal (the `accurate`
    /// prefilter's; the others run none).
    pub albedo: Option<FilterRun>,
    pub normal: Option<FilterRun>,
    /// The filter of the colour, guided by both.
    pub colour: FilterRun,
    /// The light seen directly added back.
    pub finish_seconds: f64,
}

impl Stages {
    pub fn seconds(&self) -> f64 {
        self.device_seconds
            + self.prepare_seconds
            + self.filters().iter().map(|f| f.seconds()).sum::<f64>()
            + self.finish_seconds
    }

    /// The filters that ran, in their order.
    pub fn filters(&self) -> Vec<FilterRun> {
        [self.albedo, self.normal, Some(self.colour)]
            .into_iter()
            .flatten()
            .collect()
    }
}
