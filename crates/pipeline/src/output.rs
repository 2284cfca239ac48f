//! Writing output files whole or not at all, in the format their
//! extension names.

use crate::rendered::Picture;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Why an output file was not written; the file is then as it was before.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("cannot encode the {format}")]
    Encode {
        format: &'static str,
        #[source]
        source: image::ImageError,
    },
    #[error("cannot create a file in {}", dir.display())]
    Create {
        dir: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("cannot write {}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The extension names no format the tracer writes.
    #[error(
        "{}: cannot write {}; the image formats written are: {}",
        path.display(),
        match extension { Some(e) => format!("`.{e}` files"), None => "a file without an extension".to_string() },
        ImageFormat::list()
    )]
    UnknownFormat {
        path: PathBuf,
        extension: Option<String>,
    },
    /// The output's folder does not exist (a typo, most likely).
    #[error("{}: the folder {} does not exist", path.display(), dir.display())]
    NoFolder { path: PathBuf, dir: PathBuf },
    /// The output is an existing folder, device or other non-file.
    #[error("{}: cannot write over a folder or a device; expected a file", path.display())]
    NotAFile { path: PathBuf },
    /// An image with no linear values (a chart, a plot) cannot be a float file.
    #[error("{}: only the 8-bit formats (.png, .jpg) are written for this image, not {}", path.display(), format.name())]
    EightBitOnly { path: PathBuf, format: ImageFormat },
    /// `--bit-depth 16` for another format than PNG.
    #[error("{}: --bit-depth 16 is for .png outputs; {} files are written at {}", path.display(), format.name(), match format { ImageFormat::Jpeg => "8 bits", _ => "32-bit float (linear)" })]
    BitDepthOfFormat { path: PathBuf, format: ImageFormat },
    /// `--gamma` for a file of linear values, which takes no gamma.
    #[error("{}: --gamma encodes for a display; {} files hold the renderer's linear values, without gamma", path.display(), format.name())]
    GammaOfLinear { path: PathBuf, format: ImageFormat },
    /// `--denoising-data` to another format than OpenEXR.
    #[error("{}: --denoising-data keeps the noisy image and the denoiser's guides as layers of an OpenEXR file, beside the denoised image; {} files hold one image: write to .exr", path.display(), format.name())]
    DenoisingDataFormat { path: PathBuf, format: ImageFormat },
    /// `--denoising-data` for a render that is not denoised.
    #[error("--denoising-data keeps what went into the denoiser, and this render is not denoised: add --denoise (or `denoise = true` in [render]; path mode)")]
    NotDenoised,
    /// The output is one of the files read (same file, however named).
    #[error("{}: the output is the input {}; refusing to overwrite it", path.display(), input.display())]
    IsAnInput { path: PathBuf, input: PathBuf },
}

impl OutputError {
    /// Whether the user named a wrong output (the CLI's exit status 2)
    /// rather than the machine failing to write one (1).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            OutputError::UnknownFormat { .. }
                | OutputError::IsAnInput { .. }
                | OutputError::EightBitOnly { .. }
                | OutputError::BitDepthOfFormat { .. }
                | OutputError::GammaOfLinear { .. }
                | OutputError::DenoisingDataFormat { .. }
                | OutputError::NotDenoised
        )
    }
}

/// The image file formats written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8 bits per channel, or 16 with [`BitDepth::Sixteen`].
    Png,
    /// 8 bits, encoded as the PNG, at [`JPEG_QUALITY`].
    Jpeg,
    /// OpenEXR, 32-bit floats: the renderer's linear values.
    Exr,
    /// Radiance RGBE: the linear values, 8-bit mantissas sharing an exponent.
    Hdr,
}

/// JPEG's quality (1 to 100): high enough that the lab's flat colours and
/// sharp edges keep within a few levels of the PNG.
pub const JPEG_QUALITY: u8 = 90;

/// Bits per channel of a PNG.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BitDepth {
    #[default]
    Eight,
    Sixteen,
}

impl ImageFormat {
    pub const ALL: [ImageFormat; 4] = [
        ImageFormat::Png,
        ImageFormat::Jpeg,
        ImageFormat::Exr,
        ImageFormat::Hdr,
    ];

    /// The format an output path's extension names (any case), or
    /// [`OutputError::UnknownFormat`]: writing PNG bytes to `x.tif` would
    /// give a file that lies about its contents.
    pub fn for_path(path: &Path) -> Result<ImageFormat, OutputError> {
        let extension = path.extension().map(|e| e.to_string_lossy().into_owned());
        ImageFormat::ALL
            .into_iter()
            .find(|f| {
                extension.as_deref().is_some_and(|e| {
                    f.extensions()
                        .iter()
                        .any(|known| e.eq_ignore_ascii_case(known))
                })
            })
            .ok_or(OutputError::UnknownFormat {
                path: path.to_path_buf(),
                extension,
            })
    }

    /// The extensions that name the format, the usual one first.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            ImageFormat::Png => &["png"],
            ImageFormat::Jpeg => &["jpg", "jpeg"],
            ImageFormat::Exr => &["exr"],
            ImageFormat::Hdr => &["hdr"],
        }
    }

    pub fn extension(self) -> &'static str {
        self.extensions()[0]
    }

    pub fn name(self) -> &'static str {
        match self {
            ImageFormat::Png => "PNG",
            ImageFormat::Jpeg => "JPEG",
            ImageFormat::Exr => "OpenEXR",
            ImageFormat::Hdr => "Radiance HDR",
        }
    }

    /// Whether the file holds the linear values (floats) rather than the
    /// display encoding (gamma, saturation rule, integers).
    pub fn is_linear(self) -> bool {
        matches!(self, ImageFormat::Exr | ImageFormat::Hdr)
    }

    /// ".png, .jpg, .jpeg, .exr, .hdr".
    fn list() -> String {
        let names: Vec<String> = ImageFormat::ALL
            .iter()
            .flat_map(|f| f.extensions())
            .map(|e| format!(".{e}"))
            .collect();
        names.join(", ")
    }
}

/// Refuses an output that is one of `inputs` (the same file, whatever the
/// path: `./s.toml`, a hard link, a symbolic link), before any work.
pub fn check_not_an_input<P: AsRef<Path>>(output: &Path, inputs: &[P]) -> Result<(), OutputError> {
    match inputs.iter().find(|i| same_file(output, i.as_ref())) {
        Some(input) => Err(OutputError::IsAnInput {
            path: output.to_path_buf(),
            input: input.as_ref().to_path_buf(),
        }),
        None => Ok(()),
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    let (Ok(ma), Ok(mb)) = (std::fs::metadata(a), std::fs::metadata(b)) else {
        // One does not exist: writing it cannot clobber the other.
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        ma.dev() == mb.dev() && ma.ino() == mb.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (ma, mb);
        matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
    }
}

/// Temporary files in flight, for [`remove_pending_files`] on a signal.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn pending() -> MutexGuard<'static, Vec<PathBuf>> {
    // A panic elsewhere must not keep the files from being cleaned up.
    PENDING.lock().unwrap_or_else(|e| e.into_inner())
}

/// Held while the process exits on a signal: no output is renamed into
/// place (nor a temporary file made) after the cleanup.
pub struct PendingFilesRemoved(#[allow(dead_code)] MutexGuard<'static, Vec<PathBuf>>);

/// Removes every temporary output file in flight, for a signal handler
/// that then exits; keep the guard until the exit.
pub fn remove_pending_files() -> PendingFilesRemoved {
    remove_pending_files_where(|_| true)
}

/// The files of `remove_pending_files` that `which` picks (tests run in
/// parallel: each removes its own only).
fn remove_pending_files_where(which: impl Fn(&Path) -> bool) -> PendingFilesRemoved {
    let mut list = pending();
    list.retain(|path| {
        if which(path) {
            // A pending folder (made here, under a name of its own) goes
            // with what was written into it.
            match std::fs::symlink_metadata(path) {
                Ok(m) if m.is_dir() => drop(std::fs::remove_dir_all(path)),
                _ => drop(std::fs::remove_file(path)),
            }
        }
        !which(path)
    });
    PendingFilesRemoved(list)
}

/// A folder about to take the place of another (`tracer compare
/// --report`'s report): made beside its place, filled file by file, then
/// renamed into place whole. Until then it is removed on a signal, as the
/// temporary files are, and when dropped.
pub struct PendingFolder {
    dir: Option<tempfile::TempDir>,
    path: PathBuf,
}

impl PendingFolder {
    /// Makes the folder in `parent`, named `prefix` and random letters.
    pub fn create(parent: &Path, prefix: &str) -> std::io::Result<PendingFolder> {
        let mut list = pending();
        let dir = tempfile::Builder::new().prefix(prefix).tempdir_in(parent)?;
        let path = dir.path().to_path_buf();
        list.push(path.clone());
        Ok(PendingFolder {
            dir: Some(dir),
            path,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Renames the folder to `target`, where nothing may be (a folder
    /// there is replaced only if empty, as `rename` does). After a
    /// signal's cleanup nothing is renamed: the lock is held through.
    pub fn rename_to(mut self, target: &Path) -> std::io::Result<()> {
        let mut list = pending();
        std::fs::rename(&self.path, target)?;
        // In place now: the TempDir must not remove it.
        let _ = self.dir.take().map(tempfile::TempDir::keep);
        list.retain(|p| *p != self.path);
        Ok(())
    }
}

impl Drop for PendingFolder {
    fn drop(&mut self) {
        let mut list = pending();
        // Removed (by TempDir's drop) before it leaves the list.
        drop(self.dir.take());
        list.retain(|p| *p != self.path);
    }
}

/// An output file about to be written: its format known and its temporary
/// file made in the target folder, so a bad output path fails before the
/// work (a render) rather than after it. Dropped unwritten, it leaves
/// nothing behind.
pub struct PendingOutput {
    file: PendingFile,
    format: ImageFormat,
}

/// A file about to be written whole or not at all, of any kind (an image,
/// an archive): its temporary file made in the target folder.
pub struct PendingFile {
    path: PathBuf,
    tmp: Option<tempfile::NamedTempFile>,
    tmp_path: PathBuf,
}

impl PendingFile {
    /// Checks `path` (not a folder or a device, in a folder that takes new
    /// files) and makes the temporary file.
    pub fn create(path: &Path) -> Result<PendingFile, OutputError> {
        if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
            // A rename would replace a device node, or fail on a folder.
            return Err(OutputError::NotAFile {
                path: path.to_path_buf(),
            });
        }
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if !dir.is_dir() {
            // Clearer than the temporary file's "No such file" at its path.
            return Err(OutputError::NoFolder {
                path: path.to_path_buf(),
                dir: dir.to_path_buf(),
            });
        }
        let mut builder = tempfile::Builder::new();
        builder.prefix(".tracer-").suffix(".tmp");
        #[cfg(unix)]
        builder.permissions(permissions_for(path));
        let mut list = pending();
        let tmp = builder
            .tempfile_in(dir)
            .map_err(|source| OutputError::Create {
                dir: dir.to_path_buf(),
                source,
            })?;
        let tmp_path = tmp.path().to_path_buf();
        list.push(tmp_path.clone());
        Ok(PendingFile {
            path: path.to_path_buf(),
            tmp: Some(tmp),
            tmp_path,
        })
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes `bytes` and renames the file into place, whole or not at all.
    pub fn write_bytes(mut self, bytes: &[u8]) -> Result<(), OutputError> {
        let write_error = |source| OutputError::Write {
            path: self.path.clone(),
            source,
        };
        let tmp = self.tmp.as_mut().expect("written once");
        tmp.write_all(bytes)
            .and_then(|()| tmp.as_file().sync_all())
            .map_err(write_error)?;
        let mut list = pending();
        let tmp = self.tmp.take().expect("written once");
        // On failure the temporary file is in the error and dropped: removed.
        let persisted = tmp.persist(&self.path).map(drop).map_err(|e| e.error);
        list.retain(|p| *p != self.tmp_path);
        persisted.map_err(write_error)
    }
}

impl Drop for PendingFile {
    fn drop(&mut self) {
        let mut list = pending();
        // Removed (by NamedTempFile's drop) before it leaves the list.
        drop(self.tmp.take());
        list.retain(|p| *p != self.tmp_path);
    }
}

impl PendingOutput {
    /// Checks `path` (a writable image format, not a folder or a device,
    /// a folder that takes new files) and makes the temporary file.
    pub fn create(path: &Path) -> Result<PendingOutput, OutputError> {
        let format = ImageFormat::for_path(path)?;
        Ok(PendingOutput {
            file: PendingFile::create(path)?,
            format,
        })
    }

    /// As [`create`](Self::create), for an image that has only 8-bit
    /// values (a chart, a plot): a float format is refused here, before
    /// the work, rather than when written.
    pub fn create_8bit(path: &Path) -> Result<PendingOutput, OutputError> {
        match ImageFormat::for_path(path)? {
            format if format.is_linear() => Err(OutputError::EightBitOnly {
                path: path.to_path_buf(),
                format,
            }),
            _ => PendingOutput::create(path),
        }
    }

    pub fn path(&self) -> &Path {
        &self.file.path
    }

    pub fn format(&self) -> ImageFormat {
        self.format
    }

    /// Refuses, before a render, what the output's format cannot hold: 16
    /// bits outside PNG, a display gamma (`gamma_given`) in a float file.
    pub fn check_render_options(
        &self,
        depth: BitDepth,
        gamma_given: bool,
    ) -> Result<(), OutputError> {
        let (path, format) = (self.file.path.clone(), self.format);
        if depth == BitDepth::Sixteen && format != ImageFormat::Png {
            return Err(OutputError::BitDepthOfFormat { path, format });
        }
        if gamma_given && format.is_linear() {
            return Err(OutputError::GammaOfLinear { path, format });
        }
        Ok(())
    }

    /// Refuses, before a render, `--denoising-data` (`asked`) to another
    /// format than OpenEXR.
    pub fn check_denoising_data(&self, asked: bool) -> Result<(), OutputError> {
        if asked && self.format != ImageFormat::Exr {
            return Err(OutputError::DenoisingDataFormat {
                path: self.file.path.clone(),
                format: self.format,
            });
        }
        Ok(())
    }

    /// Encodes an 8-bit `image` (PNG or JPEG) and writes it into place; a
    /// float format is [`OutputError::EightBitOnly`].
    pub fn write_image(self, image: &image::RgbImage) -> Result<(), OutputError> {
        if self.format.is_linear() {
            return Err(OutputError::EightBitOnly {
                path: self.file.path.clone(),
                format: self.format,
            });
        }
        let bytes = encode(image, self.format)?;
        self.write_bytes(&bytes)
    }

    /// Encodes a render in the output's format and writes it into place:
    /// PNG at `depth` bits, JPEG at 8, EXR and HDR the linear values. The
    /// caller has refused 16 bits for other formats than PNG (it is
    /// ignored here).
    pub fn write_picture(self, picture: &Picture, depth: BitDepth) -> Result<(), OutputError> {
        let bytes = match (self.format, depth) {
            (ImageFormat::Png, BitDepth::Sixteen) => encode_dynamic(
                image::DynamicImage::ImageRgb16(picture.to_rgb16()),
                self.format,
            )?,
            (ImageFormat::Exr, _) => encode_exr(&picture.to_rgb32f())?,
            (ImageFormat::Hdr, _) => encode_dynamic(
                image::DynamicImage::ImageRgb32F(clamped_to_rgbe(picture.to_rgb32f())),
                self.format,
            )?,
            _ => encode(&picture.to_rgb8(), self.format)?,
        };
        self.write_bytes(&bytes)
    }

    /// Writes `bytes` and renames the file into place, whole or not at all.
    pub fn write_bytes(self, bytes: &[u8]) -> Result<(), OutputError> {
        self.file.write_bytes(bytes)
    }

    /// What `write_picture` cannot write as it is, in words: a Radiance
    /// .hdr's values above [`RGBE_MAX`], written as that.
    pub fn picture_warning(&self, picture: &Picture) -> Option<String> {
        if self.format != ImageFormat::Hdr {
            return None;
        }
        let over = picture
            .linear
            .pixels
            .iter()
            .filter(|p| p.max_element() > RGBE_MAX)
            .count();
        (over > 0).then(|| {
            format!(
                "{over} pixel(s) hold values above {RGBE_MAX:.3e}, the largest a Radiance .hdr holds \
                 (its 8-bit mantissas share an exponent of at most 2^127): written as that value; \
                 an .exr holds them as they are"
            )
        })
    }
}

/// The largest value a Radiance RGBE pixel holds: mantissa 255 of 256 at
/// the largest exponent, 2^127 (about 1.69e38). Larger values encode as
/// black in the image crate's encoder (their exponent overflows).
pub const RGBE_MAX: f32 = 255.0 * (1u128 << 119) as f32;

/// `image` with every channel above [`RGBE_MAX`] brought down to it.
fn clamped_to_rgbe(mut image: image::Rgb32FImage) -> image::Rgb32FImage {
    for value in image.iter_mut() {
        *value = value.min(RGBE_MAX);
    }
    image
}

/// Writes `image` to `path`, in the format of its extension, through a
/// temporary file in the same folder and a rename: a failure leaves no
/// partial file and an existing image untouched.
pub fn write_image(image: &image::RgbImage, path: &Path) -> Result<(), OutputError> {
    PendingOutput::create(path)?.write_image(image)
}

/// The bytes of an 8-bit image file in `format` (PNG's are those of
/// every release so far: the goldens check them).
pub fn encode(image: &image::RgbImage, format: ImageFormat) -> Result<Vec<u8>, OutputError> {
    if format == ImageFormat::Jpeg {
        // `write_to` would take the encoder's default quality (75).
        return encoded_with(format, |bytes| {
            image::codecs::jpeg::JpegEncoder::new_with_quality(bytes, JPEG_QUALITY)
                .encode_image(image)
        });
    }
    encoded_with(format, |bytes| {
        image.write_to(&mut std::io::Cursor::new(bytes), image_format(format))
    })
}

/// The bytes of a 16-bit or float image file in `format`.
fn encode_dynamic(image: image::DynamicImage, format: ImageFormat) -> Result<Vec<u8>, OutputError> {
    encoded_with(format, |bytes| {
        image.write_to(&mut std::io::Cursor::new(bytes), image_format(format))
    })
}

/// The bytes of an OpenEXR file of `image` (RLE-compressed, as the image
/// crate writes it), its blocks written one after the other: the image
/// crate compresses them on several threads and writes them as they come,
/// so the same pixels gave other bytes from run to run.
fn encode_exr(image: &image::Rgb32FImage) -> Result<Vec<u8>, OutputError> {
    use exr::prelude::WritableImage;
    use exr::prelude::{Encoding, Image, Layer, LayerAttributes, SpecificChannels, Vec2};
    let (width, height) = (image.width() as usize, image.height() as usize);
    let layer = Layer::new(
        (width, height),
        LayerAttributes::default(),
        Encoding::FAST_LOSSLESS,
        SpecificChannels::rgb(|p: Vec2<usize>| {
            let [r, g, b] = image.get_pixel(p.x() as u32, p.y() as u32).0;
            (r, g, b)
        }),
    );
    let mut bytes = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .non_parallel()
        .to_buffered(&mut bytes)
        .map_err(exr_error)?;
    Ok(bytes.into_inner())
}

/// The exr crate's failure to encode, as an output error.
pub(crate) fn exr_error(e: exr::error::Error) -> OutputError {
    OutputError::Encode {
        format: ImageFormat::Exr.name(),
        source: image::ImageError::Encoding(image::error::EncodingError::new(
            image::error::ImageFormatHint::Exact(image::ImageFormat::OpenExr),
            e,
        )),
    }
}

/// The bytes `write` encodes, its failure named as `format`'s.
fn encoded_with(
    format: ImageFormat,
    write: impl FnOnce(&mut Vec<u8>) -> image::ImageResult<()>,
) -> Result<Vec<u8>, OutputError> {
    let mut bytes = Vec::new();
    write(&mut bytes).map_err(|source| OutputError::Encode {
        format: format.name(),
        source,
    })?;
    Ok(bytes)
}

fn image_format(format: ImageFormat) -> image::ImageFormat {
    match format {
        ImageFormat::Png => image::ImageFormat::Png,
        ImageFormat::Jpeg => image::ImageFormat::Jpeg,
        ImageFormat::Exr => image::ImageFormat::OpenExr,
        ImageFormat::Hdr => image::ImageFormat::Hdr,
    }
}

/// Writes `bytes` to `path` whole or not at all (see `write_image`).
pub fn write_atomically(bytes: &[u8], path: &Path) -> Result<(), OutputError> {
    PendingOutput::create(path)?.write_bytes(bytes)
}

/// The mode of the file being replaced, or an ordinary file's (rw-r--r--,
/// less the umask): a temporary file is created readable by its owner
/// only, and the renamed image would keep that.
#[cfg(unix)]
fn permissions_for(path: &Path) -> std::fs::Permissions {
    use std::os::unix::fs::PermissionsExt;
    let mode = std::fs::metadata(path).map_or(0o644, |m| m.permissions().mode() & 0o7777);
    std::fs::Permissions::from_mode(mode)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter(|n| n.starts_with(".tracer-"))
            .collect()
    }

    #[test]
    fn an_exr_is_the_same_bytes_every_time_and_reads_back_bit_for_bit() {
        // Tall enough for many blocks (16 rows each), which the image
        // crate compressed on several threads and wrote as they came.
        let (w, h) = (64u32, 400u32);
        let value =
            |i: u32| f32::from_bits(0x3000_0000 + i.wrapping_mul(2_654_435_761) % 0x1800_0000);
        let image = image::Rgb32FImage::from_fn(w, h, |x, y| {
            let i = 3 * (y * w + x);
            image::Rgb([value(i), -value(i + 1), value(i + 2)])
        });
        let first = encode_exr(&image).unwrap();
        for _ in 0..4 {
            assert!(encode_exr(&image).unwrap() == first, "other bytes");
        }
        let back = image::load_from_memory_with_format(&first, image::ImageFormat::OpenExr)
            .unwrap()
            .into_rgb32f();
        let bits =
            |i: &image::Rgb32FImage| i.as_raw().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&back), bits(&image));
    }

    #[test]
    fn a_write_replaces_the_old_file_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.png");
        std::fs::write(&path, b"an old, longer image file").unwrap();
        write_atomically(b"new", &path).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_failed_write_leaves_the_target_and_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        // The rename onto a non-empty folder fails after the data is written.
        let target = dir.path().join("image.png");
        std::fs::create_dir(&target).unwrap();
        std::fs::write(target.join("keep"), b"old").unwrap();
        assert!(write_atomically(b"new", &target).is_err());
        assert_eq!(std::fs::read(target.join("keep")).unwrap(), b"old");
        assert!(leftovers(dir.path()).is_empty());
    }

    #[cfg(unix)]
    #[test]
    fn a_new_file_is_readable_by_all_and_a_replaced_one_keeps_its_mode() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let new = dir.path().join("new.png");
        write_atomically(b"new", &new).unwrap();
        // As a plain write would make it (0o666 less the umask), less
        // others' and the group's write permission.
        let plain = dir.path().join("plain.png");
        std::fs::write(&plain, b"plain").unwrap();
        assert_eq!(mode(&new), mode(&plain) & 0o644);
        let old = dir.path().join("old.png");
        std::fs::write(&old, b"old").unwrap();
        std::fs::set_permissions(&old, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomically(b"new", &old).unwrap();
        assert_eq!(mode(&old), 0o640);
    }

    #[test]
    fn hdr_values_beyond_rgbe_are_written_as_its_largest_and_said() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.hdr");
        let mut linear = tracer_core::image::LinearImage::new(3, 1);
        // An emission of 3e38 is accepted; RGBE overflows at 2^127 (1.7e38).
        linear.pixels[0] = glam::Vec3::new(3e38, 1.0, 0.0);
        linear.pixels[1] = glam::Vec3::splat(1e38);
        linear.pixels[2] = glam::Vec3::new(1.0, 0.5, 0.25);
        let picture = Picture {
            linear,
            encoding: tracer_core::image::Encoding::default(),
        };
        let pending = PendingOutput::create(&path).unwrap();
        let warning = pending.picture_warning(&picture).expect("a warning");
        assert!(
            warning.starts_with("1 pixel(s) hold values above 1.695e38"),
            "{warning}"
        );
        pending.write_picture(&picture, BitDepth::Eight).unwrap();
        let read = image::open(&path).unwrap().to_rgb32f();
        let [r, g, _] = read.get_pixel(0, 0).0;
        assert!(r > 1.6e38 && r <= RGBE_MAX, "{r:e}: not black");
        // Its other channels share the large exponent: their mantissas are 0.
        assert_eq!(g, 0.0);
        let [big, ..] = read.get_pixel(1, 0).0;
        assert!((big / 1e38 - 1.0).abs() < 0.01, "{big:e}");
        assert_eq!(read.get_pixel(2, 0).0, [1.0, 0.5, 0.25]);
        let small = PendingOutput::create(&dir.path().join("s.exr")).unwrap();
        assert_eq!(small.picture_warning(&picture), None);
    }

    #[test]
    fn a_missing_folder_is_an_error_not_a_panic() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no/such/folder/out.png");
        let err = write_atomically(b"new", &path).unwrap_err();
        assert!(
            err.to_string().ends_with("no/such/folder does not exist"),
            "{err}"
        );
        assert!(!path.exists());
    }

    #[test]
    fn the_extension_decides_the_format_and_others_are_refused_up_front() {
        let dir = tempfile::tempdir().unwrap();
        let image = image::RgbImage::from_pixel(3, 2, image::Rgb([10, 20, 30]));
        for (name, magic) in [
            ("a.png", &b"\x89PNG"[..]),
            ("b.PNG", b"\x89PNG"),
            ("c.jpg", b"\xff\xd8\xff"),
            ("c2.JPEG", b"\xff\xd8\xff"),
        ] {
            let path = dir.path().join(name);
            write_image(&image, &path).unwrap();
            assert!(std::fs::read(&path).unwrap().starts_with(magic), "{name}");
        }
        let picture = Picture {
            linear: tracer_core::image::LinearImage::new(3, 2),
            encoding: tracer_core::image::Encoding::default(),
        };
        for (name, magic) in [
            ("e.exr", &b"\x76\x2f\x31\x01"[..]),
            ("f.hdr", b"#?RADIANCE"),
            ("g.png", b"\x89PNG"),
        ] {
            let path = dir.path().join(name);
            let pending = PendingOutput::create(&path).unwrap();
            pending.write_picture(&picture, BitDepth::Eight).unwrap();
            assert!(std::fs::read(&path).unwrap().starts_with(magic), "{name}");
        }
        // A chart or a plot has no linear values to put in a float file.
        let err = write_image(&image, &dir.path().join("h.exr")).unwrap_err();
        assert!(err.is_bad_input(), "{err}");
        assert!(!dir.path().join("h.exr").exists());
        let err = PendingOutput::create_8bit(&dir.path().join("h.hdr"))
            .err()
            .unwrap();
        assert!(matches!(err, OutputError::EightBitOnly { .. }), "{err}");
        for (name, found) in [
            ("c.tif", "`.tif` files"),
            ("d.webp", "`.webp` files"),
            ("noext", "a file without an extension"),
            ("scene.toml", "`.toml` files"),
        ] {
            let path = dir.path().join(name);
            let err = PendingOutput::create(&path).err().unwrap();
            assert!(err.is_bad_input());
            let message = err.to_string();
            assert!(message.contains(found), "{message}");
            assert!(
                message.ends_with("the image formats written are: .png, .jpg, .jpeg, .exr, .hdr"),
                "{message}"
            );
            assert!(!path.exists());
        }
        assert!(leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_bad_output_folder_fails_when_the_output_is_created_not_when_written() {
        let dir = tempfile::tempdir().unwrap();
        let missing = PendingOutput::create(&dir.path().join("no/out.png"));
        assert!(matches!(missing, Err(OutputError::NoFolder { .. })));
        std::fs::create_dir(dir.path().join("folder.png")).unwrap();
        let folder = PendingOutput::create(&dir.path().join("folder.png"));
        assert!(matches!(folder, Err(OutputError::NotAFile { .. })));
        #[cfg(unix)]
        {
            let device = dir.path().join("null.png");
            std::os::unix::fs::symlink("/dev/null", &device).unwrap();
            let device = PendingOutput::create(&device);
            assert!(matches!(device, Err(OutputError::NotAFile { .. })));
        }
        // A good one holds its temporary file until written or dropped.
        let pending = PendingOutput::create(&dir.path().join("ok.png")).unwrap();
        assert_eq!(leftovers(dir.path()).len(), 1);
        drop(pending);
        assert!(leftovers(dir.path()).is_empty());
        assert!(!dir.path().join("ok.png").exists());
    }

    #[test]
    fn pending_files_are_removed_for_a_signal() {
        let dir = tempfile::tempdir().unwrap();
        let pending = PendingOutput::create(&dir.path().join("out.png")).unwrap();
        let written = PendingOutput::create(&dir.path().join("done.png")).unwrap();
        written.write_bytes(b"done").unwrap();
        drop(remove_pending_files_where(|p| p.starts_with(dir.path())));
        assert!(leftovers(dir.path()).is_empty());
        assert_eq!(std::fs::read(dir.path().join("done.png")).unwrap(), b"done");
        drop(pending);
    }

    #[test]
    fn an_output_that_is_an_input_is_refused_however_it_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let input = dir.path().join("m.png");
        std::fs::write(&input, b"input").unwrap();
        let link = dir.path().join("link.png");
        std::fs::hard_link(&input, &link).unwrap();
        let dotted = dir.path().join(".").join("m.png");
        for output in [&input, &link, &dotted] {
            let err = check_not_an_input(output, &[&input]).unwrap_err();
            assert!(err.is_bad_input());
            assert!(err.to_string().contains("refusing to overwrite"), "{err}");
        }
        let other = dir.path().join("other.png");
        check_not_an_input(&other, &[&input]).unwrap();
        std::fs::write(&other, b"other").unwrap();
        check_not_an_input(&other, &[&input]).unwrap();
    }
}
