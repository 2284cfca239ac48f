//! OIDN's `RT` filter run on the images in place: a CPU device, and the
//! guides treated as Blender's "Prefilter" says. `accurate` (the default):
//! the albedo and normal prefiltered first and then given with `cleanAux`,
//! as OIDN's documentation advises for final frames; `fast`: given as they
//! are, without `cleanAux` (the filter's network for noisy guides);
//! `none`: given as they are, with `cleanAux` (taken as clean). The images
//! are OIDN's "shared" images, our own pixels, so nothing is copied.

use super::library::{c_name, Api, Handle};
use super::stages::FilterRun;
use super::{oidn_quality, quality_of_oidn, DenoiseError, Prefilter, Quality, Settings};
use glam::Vec3;
use std::ffi::{c_void, CStr};
use std::time::Instant;

/// `OIDN_DEVICE_TYPE_CPU`.
const DEVICE_CPU: i32 = 1;
/// `OIDN_FORMAT_FLOAT3`: three f32 a pixel, as glam's `Vec3`.
const FORMAT_FLOAT3: i32 = 3;
const _: () = assert!(std::mem::size_of::<Vec3>() == 12);

/// A CPU device, released when dropped.
pub(super) struct Device {
    api: &'static Api,
    handle: Handle,
}

impl Device {
    /// A committed CPU device of `threads` threads (0: OIDN's choice, one
    /// per core).
    pub(super) fn new(api: &'static Api, threads: usize) -> Result<Device, DenoiseError> {
        // SAFETY: OIDN's C API, called as oidn.h declares it.
        let handle = unsafe { (api.new_device)(DEVICE_CPU) };
        if handle.is_null() {
            return Err(DenoiseError::Oidn(
                "no CPU device could be made (oidnNewDevice)".to_string(),
            ));
        }
        let device = Device { api, handle };
        let threads = i32::try_from(threads).unwrap_or(0);
        // SAFETY: as above; the name is NUL-terminated.
        unsafe {
            (api.set_device_int)(handle, c_name(c"numThreads"), threads);
            (api.commit_device)(handle);
        }
        device.check()?;
        Ok(device)
    }

    /// OIDN's version, e.g. 20501 for 2.5.1.
    pub(super) fn version(&self) -> i32 {
        // SAFETY: as above.
        unsafe { (self.api.get_device_int)(self.handle, c_name(c"version")) }
    }

    /// The device's first error since the last check, if any.
    fn check(&self) -> Result<(), DenoiseError> {
        let mut message = std::ptr::null();
        // SAFETY: as above; OIDN's message lives until the next call.
        let code = unsafe { (self.api.get_device_error)(self.handle, &mut message) };
        if code == 0 {
            return Ok(());
        }
        let text = if message.is_null() {
            String::new()
        } else {
            // SAFETY: a NUL-terminated string from OIDN.
            unsafe { CStr::from_ptr(message) }
                .to_string_lossy()
                .into_owned()
        };
        Err(DenoiseError::Oidn(format!("error {code}: {text}")))
    }

    /// The `RT` filter on `colour` (HDR, linear), guided by `albedo` and
    /// `normal` (prefiltered here, in place, if `settings` say so), into
    /// `output`: all `width` x `height`, rows top to bottom. Every filter
    /// at the quality asked, as Blender's Cycles does (OIDN has no fast
    /// network for the guides: at `fast` it runs its balanced one on them).
    pub(super) fn denoise(
        &self,
        (width, height): (usize, usize),
        colour: &[Vec3],
        albedo: &mut [Vec3],
        normal: &mut [Vec3],
        output: &mut [Vec3],
        settings: Settings,
    ) -> Result<Runs, DenoiseError> {
        let size = width * height;
        assert!(
            [colour.len(), albedo.len(), normal.len(), output.len()] == [size; 4],
            "every image is width x height"
        );
        let image = Image { width, height };
        let quality = settings.quality;
        let prefilter = |name: &'static CStr, pixels: &mut [Vec3]| {
            if settings.prefilter != Prefilter::Accurate {
                return Ok(None);
            }
            let filter = Filter::new(self, quality)?;
            filter.set(name, image, pixels.as_mut_ptr());
            filter.set(c"output", image, pixels.as_mut_ptr());
            Ok::<_, DenoiseError>(Some(filter))
        };
        let albedo_filter = prefilter(c"albedo", albedo)?;
        let normal_filter = prefilter(c"normal", normal)?;
        let filter = Filter::new(self, quality)?;
        // OIDN only reads its inputs: the cast to *mut is its C signature.
        filter.set(c"color", image, colour.as_ptr().cast_mut());
        filter.set(c"albedo", image, albedo.as_mut_ptr());
        filter.set(c"normal", image, normal.as_mut_ptr());
        filter.set(c"output", image, output.as_mut_ptr());
        filter.set_bool(c"hdr", true);
        filter.set_bool(c"cleanAux", settings.prefilter != Prefilter::Fast);
        // OIDN's working memory is one heap a device, freed when a filter
        // is released and no other holds it. All committed before any
        // runs (as Blender does), they share it and only the first run
        // pays for touching its pages; run and released one at a time,
        // each paid for its own (1.5 s of a fast denoise's 24 on
        // 1920x1080, 6 %).
        let albedo_commit = albedo_filter.as_ref().map(Filter::commit).transpose()?;
        let normal_commit = normal_filter.as_ref().map(Filter::commit).transpose()?;
        let colour_commit = filter.commit()?;
        let execute = |f: Option<&Filter>, commit: Option<f64>| {
            f.zip(commit).map(|(f, c)| f.execute(c)).transpose()
        };
        Ok(Runs {
            albedo: execute(albedo_filter.as_ref(), albedo_commit)?,
            normal: execute(normal_filter.as_ref(), normal_commit)?,
            colour: filter.execute(colour_commit)?,
        })
    }
}

/// The runs of one denoise's filters: the guides' prefilters where there
/// are, and the colour's filter.
pub(super) struct Runs {
    pub albedo: Option<FilterRun>,
    pub normal: Option<FilterRun>,
    pub colour: FilterRun,
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: the handle is ours, released once.
        unsafe { (self.api.release_device)(self.handle) }
    }
}

/// The size of an image given to a filter.
#[derive(Clone, Copy)]
struct Image {
    width: usize,
    height: usize,
}

/// An `RT` filter of a device, released when dropped.
struct Filter<'d> {
    device: &'d Device,
    handle: Handle,
}

impl<'d> Filter<'d> {
    fn new(device: &'d Device, quality: Quality) -> Result<Filter<'d>, DenoiseError> {
        let api = device.api;
        // SAFETY: as above.
        let handle = unsafe { (api.new_filter)(device.handle, c_name(c"RT")) };
        device.check()?;
        if handle.is_null() {
            return Err(DenoiseError::Oidn(
                "no RT filter (oidnNewFilter)".to_string(),
            ));
        }
        let filter = Filter { device, handle };
        // SAFETY: as above.
        unsafe { (api.set_filter_int)(handle, c_name(c"quality"), oidn_quality(quality)) };
        Ok(filter)
    }

    /// Image `name` at `pixels` (which must outlive the filter's run).
    fn set(&self, name: &'static CStr, image: Image, pixels: *mut Vec3) {
        let stride = std::mem::size_of::<Vec3>();
        // SAFETY: `pixels` holds width * height pixels of 3 f32, rows
        // packed, and lives until `run` returns (the caller's borrow).
        unsafe {
            (self.device.api.set_shared_filter_image)(
                self.handle,
                c_name(name),
                pixels.cast::<c_void>(),
                FORMAT_FLOAT3,
                image.width,
                image.height,
                0,
                stride,
                stride * image.width,
            )
        }
    }

    fn set_bool(&self, name: &'static CStr, value: bool) {
        // SAFETY: as above.
        unsafe { (self.device.api.set_filter_bool)(self.handle, c_name(name), value) }
    }

    /// Commits the filter: the seconds it took.
    fn commit(&self) -> Result<f64, DenoiseError> {
        let start = Instant::now();
        // SAFETY: as above.
        unsafe { (self.device.api.commit_filter)(self.handle) };
        self.device.check()?;
        Ok(start.elapsed().as_secs_f64())
    }

    /// Executes the committed filter (synchronously: OIDN's
    /// `oidnExecuteFilter` waits for it), after a commit of `commit_seconds`.
    fn execute(&self, commit_seconds: f64) -> Result<FilterRun, DenoiseError> {
        let api = self.device.api;
        let start = Instant::now();
        // SAFETY: as above.
        unsafe { (api.execute_filter)(self.handle) };
        let execute_seconds = start.elapsed().as_secs_f64();
        self.device.check()?;
        // SAFETY: as above.
        let quality = unsafe { (api.get_filter_int)(self.handle, c_name(c"quality")) };
        Ok(FilterRun {
            quality: quality_of_oidn(quality),
            commit_seconds,
            execute_seconds,
        })
    }
}

impl Drop for Filter<'_> {
    fn drop(&mut self) {
        // SAFETY: the handle is ours, released once.
        unsafe { (self.device.api.release_filter)(self.handle) }
    }
}
