//! Writing images: binary PPM (P6, as report 004 writes), PNG, PFM or
//! OpenEXR (`openexr`), always to a temporary file in the target folder that is renamed into place, so an
//! interrupted run never leaves a half-written image.

pub mod openexr;

use crate::color::Rgb;
use std::io::Write;
use std::path::{Path, PathBuf};

/// An RGB image in linear [0, 1] colour, row-major from the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    pub width: usize,
    pub height: usize,
    pub pixels: Vec<Rgb>,
}

impl Image {
    pub fn new(width: usize, height: usize) -> Self {
        Image { width, height, pixels: vec![Rgb::BLACK; width * height] }
    }

    pub fn get(&self, x: usize, y: usize) -> Rgb {
        self.pixels[y * self.width + x]
    }

    /// 8-bit RGB bytes; values are clamped (report 004 clamps colours to
    /// [0, 1] before scaling to 0-255) and NaN is written as 0.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels.iter().flat_map(|p| p.to_u8()).collect()
    }
}

crate::named_enum! {
    /// What an output image is written as, chosen by its extension.
    pub enum ImageFormat {
        /// PNG, 8-bit sRGB.
        Png = "png",
        /// Binary PPM (P6), 8-bit sRGB, as report 004 writes it.
        Ppm = "ppm",
        /// Portable float map: linear sRGB, for measurement.
        Pfm = "pfm",
        /// OpenEXR: linear sRGB and CIE XYZ, half or float, for measurement.
        Exr = "exr",
    }
}

/// Why an output path is refused, before any work (one line, for the
/// caller to prefix with the flag, the file's line or the prompt).
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    #[error("the file name is empty")]
    Unnamed,
    #[error("{} is a folder; name an image file in it", .0.display())]
    Folder(PathBuf),
    #[error("{} is a symbolic link; name the file itself", .0.display())]
    Link(PathBuf),
    #[error("{} is not a regular file (a device, FIFO or socket); refract replaces only regular files", .0.display())]
    NotRegular(PathBuf),
    /// The extensions allowed, written `.png, .ppm`.
    #[error("`{}` does not end in an image extension refract writes here ({allowed})", .path.display())]
    Extension { path: PathBuf, allowed: String },
    #[error("folder {} does not exist", .0.display())]
    NoFolder(PathBuf),
    #[error("cannot write in the folder {}: {source}", .dir.display())]
    NotWritable { dir: PathBuf, source: std::io::Error },
}

/// Why an output was not written: each names the file. Nothing is left
/// at the path, nor a temporary file beside it.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    #[error("writing {}: cannot create {}: {io}", .path.display(), .tmp.display())]
    Create { path: PathBuf, tmp: PathBuf, io: std::io::Error },
    /// Filling the temporary file failed (the disk, or the encoder).
    #[error("writing {}: {io}", .path.display())]
    Fill { path: PathBuf, io: std::io::Error },
    #[error("writing {}: cannot move the output into place at {}: {io}", .path.display(), .path.display())]
    Rename { path: PathBuf, io: std::io::Error },
    #[error("{}: {bad} of {total} pixels came out NaN or infinite; nothing written", .path.display())]
    NonFinite { path: PathBuf, bad: usize, total: usize },
    #[error("{} is not a folder", .0.display())]
    NotFolder(PathBuf),
    #[error("cannot create the folder {}: {io}", .path.display())]
    Folder { path: PathBuf, io: std::io::Error },
}

/// Why a PPM was not read back, naming the file.
#[derive(Debug, thiserror::Error)]
pub enum PpmError {
    #[error("cannot read {}: {io}", .path.display())]
    Read { path: PathBuf, io: std::io::Error },
    #[error("{}: not an 8-bit P6 PPM", .0.display())]
    Format(PathBuf),
    #[error("{}: expected {expected} bytes of pixels, found {found}", .path.display())]
    Size { path: PathBuf, expected: usize, found: usize },
}

/// Checks an output path before any work is done: an extension among
/// `allowed`, a folder that exists, and at the path nothing yet or a
/// regular file (the output replaces only regular files: never a folder,
/// a device, a FIFO or a link).
pub fn check_output(path: &Path, allowed: &[ImageFormat]) -> Result<ImageFormat, OutputError> {
    use crate::names::Named;
    let names = || allowed.iter().map(|f| format!(".{}", f.name())).collect::<Vec<_>>().join(", ");
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let format = ImageFormat::from_name(&ext).filter(|f| allowed.contains(f));
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => return Err(OutputError::Folder(path.into())),
        Ok(m) if m.file_type().is_symlink() => return Err(OutputError::Link(path.into())),
        Ok(m) if !m.is_file() => return Err(OutputError::NotRegular(path.into())),
        _ => {}
    }
    let Some(format) = format else { return Err(OutputError::Extension { path: path.into(), allowed: names() }) };
    match path.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(dir) if !dir.is_dir() => Err(OutputError::NoFolder(dir.into())),
        _ => check_writable(path).map(|_| format),
    }
}

/// Checks, before any work, that the folder of `path` takes a new file: the
/// temporary file the output would be written to is made and removed.
pub fn check_writable(path: &Path) -> Result<(), OutputError> {
    let tmp = temp_sibling(path);
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
    match std::fs::OpenOptions::new().write(true).create_new(true).open(&tmp) {
        Ok(_) => {
            let _ = std::fs::remove_file(&tmp);
            Ok(())
        }
        Err(source) => Err(OutputError::NotWritable { dir: dir.into(), source }),
    }
}

/// Writes `bytes` (8-bit RGB) as PNG if the name ends in `.png`, else PPM.
pub fn write_rgb8(path: &Path, width: usize, height: usize, bytes: &[u8]) -> Result<(), WriteError> {
    let png = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("png"));
    atomic_write(path, |file| {
        if png {
            let enc = image::codecs::png::PngEncoder::new(file);
            image::ImageEncoder::write_image(enc, bytes, width as u32, height as u32, image::ExtendedColorType::Rgb8).map_err(std::io::Error::other)?;
        } else {
            write!(file, "P6\n{width} {height}\n255\n")?;
            file.write_all(bytes)?;
        }
        Ok(())
    })
}

/// Writes `width` x `height` floats (three a pixel, `pixel(i)` for pixel
/// `i` counted row-major from the top) as a portable float map:
/// little-endian, rows bottom to top.
pub fn write_pfm(path: &Path, width: usize, height: usize, pixel: impl Fn(usize) -> [f32; 3]) -> Result<(), WriteError> {
    atomic_write(path, |f| {
        write!(f, "PF\n{width} {height}\n-1.0\n")?;
        for y in (0..height).rev() {
            for x in 0..width {
                for v in pixel(y * width + x) {
                    f.write_all(&v.to_le_bytes())?;
                }
            }
        }
        Ok(())
    })
}

/// Writes the image: `display` (8-bit RGB, the image as shown) to a .png
/// or .ppm, the image's own values to a .pfm. Refuses, naming the count,
/// an image with NaN or infinite pixels (they would otherwise show as
/// black).
pub fn write_image(path: &Path, img: &Image, display: &[u8]) -> Result<(), WriteError> {
    let bad = img.pixels.iter().filter(|p| !p.is_finite()).count();
    if bad > 0 {
        return Err(WriteError::NonFinite { path: path.into(), bad, total: img.pixels.len() });
    }
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("pfm")) {
        return write_pfm(path, img.width, img.height, |i| img.pixels[i].0.to_array());
    }
    write_rgb8(path, img.width, img.height, display)
}

/// Writes text to `path` through a temporary file and a rename.
pub fn write_text(path: &Path, text: &str) -> Result<(), WriteError> {
    atomic_write(path, |f| f.write_all(text.as_bytes()))
}

/// Makes the folder `path` (and its parents) for outputs. The one-line
/// error names it: a file in the way, or why it cannot be made.
pub fn create_folder(path: &Path) -> Result<(), WriteError> {
    if path.exists() && !path.is_dir() {
        return Err(WriteError::NotFolder(path.into()));
    }
    std::fs::create_dir_all(path).map_err(|io| WriteError::Folder { path: path.into(), io })
}

/// Creates `path` through a temporary sibling file and a rename. `fill`
/// writes the contents; an encoder's own error goes in as
/// `std::io::Error::other`.
pub fn atomic_write(path: &Path, fill: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>) -> Result<(), WriteError> {
    let tmp = temp_sibling(path);
    let file = std::fs::File::create(&tmp).map_err(|io| WriteError::Create { path: path.into(), tmp: tmp.clone(), io })?;
    let filled = (|| {
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        w.flush()?;
        w.into_inner().map_err(|e| e.into_error())?.sync_all()
    })();
    let result = match filled {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|io| WriteError::Rename { path: path.into(), io }),
        Err(io) => Err(WriteError::Fill { path: path.into(), io }),
    };
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Removes the temporary files (`.NAME.TOKEN.tmp`, `TOKEN` naming the
/// refract that wrote it: `owner::Owner::token`) that a refract killed
/// while writing left in `dir`: only those whose owner is provably gone
/// (`Owner::gone`). Other programs' files, and files of a refract this
/// process cannot see (another host or container), stay. Returns how many
/// went. Errors (a folder that cannot be read) are ignored: this is
/// tidying, not work.
pub fn remove_stale_temps(dir: &Path) -> usize {
    let me = crate::owner::Owner::me();
    remove_temps(dir, |token| crate::owner::Owner::token_gone(token, &me))
}

/// Removes this process's own temporary files in `dir` (a write cut short
/// by an interruption).
pub fn remove_own_temps(dir: &Path) -> usize {
    let mine = crate::owner::Owner::me().token();
    remove_temps(dir, |token| token == mine)
}

fn remove_temps(dir: &Path, remove: impl Fn(&str) -> bool) -> usize {
    let Ok(entries) = std::fs::read_dir(if dir.as_os_str().is_empty() { Path::new(".") } else { dir }) else { return 0 };
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(stem) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else { continue };
        let Some((_, token)) = stem.rsplit_once('.') else { continue };
        if remove(token) && e.file_type().is_ok_and(|t| t.is_file()) && std::fs::remove_file(e.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

fn temp_sibling(path: &Path) -> PathBuf {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    path.with_file_name(format!(".{name}.{}.tmp", crate::owner::Owner::me().token()))
}

/// Reads a P6 PPM (used by tests and to compare runs).
pub fn read_ppm(path: &Path) -> Result<(usize, usize, Vec<u8>), PpmError> {
    let data = std::fs::read(path).map_err(|io| PpmError::Read { path: path.into(), io })?;
    let mut fields = Vec::new();
    let mut i = 0;
    while fields.len() < 4 && i < data.len() {
        while i < data.len() && data[i].is_ascii_whitespace() {
            i += 1;
        }
        let start = i;
        while i < data.len() && !data[i].is_ascii_whitespace() {
            i += 1;
        }
        fields.push(String::from_utf8_lossy(&data[start..i]).into_owned());
    }
    let size = match fields.as_slice() {
        [p6, w, h, max] if p6 == "P6" && max == "255" => w.parse::<usize>().ok().zip(h.parse::<usize>().ok()),
        _ => None,
    };
    let Some((w, h)) = size else { return Err(PpmError::Format(path.into())) };
    let body = data.get(i + 1..).unwrap_or_default();
    if body.len() != w * h * 3 {
        return Err(PpmError::Size { path: path.into(), expected: w * h * 3, found: body.len() });
    }
    Ok((w, h, body.to_vec()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A write that fails part way names the file and the cause, and
    /// leaves nothing: neither the output nor its temporary file.
    #[test]
    fn a_failed_write_names_the_file_and_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        let e = atomic_write(&path, |f| {
            f.write_all(b"half")?;
            Err(std::io::Error::other("the encoder gave up"))
        })
        .unwrap_err();
        assert!(matches!(e, WriteError::Fill { .. }), "{e:?}");
        assert_eq!(e.to_string(), format!("writing {}: the encoder gave up", path.display()));
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "something was left");
        // Into a folder that does not exist: the temporary file is named.
        let lost = dir.path().join("no").join("b.txt");
        let e = write_text(&lost, "x").unwrap_err().to_string();
        assert!(e.starts_with(&format!("writing {}: cannot create ", lost.display())) && e.contains(".tmp"), "{e}");
    }

    #[test]
    fn a_written_file_replaces_the_old_one_whole() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        write_text(&path, "first, longer").unwrap();
        write_text(&path, "second").unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "second");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn non_finite_pixels_are_refused_with_their_count() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let mut img = Image::new(3, 1);
        img.pixels[1] = Rgb::new(0.0, f32::NAN, 0.0);
        let e = write_image(&path, &img, &img.to_rgb8()).unwrap_err().to_string();
        assert_eq!(e, format!("{}: 1 of 3 pixels came out NaN or infinite; nothing written", path.display()));
        assert!(!path.exists());
    }

    #[test]
    fn a_folder_in_the_way_of_a_file_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plain");
        std::fs::write(&file, "").unwrap();
        assert_eq!(create_folder(&file).unwrap_err().to_string(), format!("{} is not a folder", file.display()));
        let e = create_folder(&file.join("sub")).unwrap_err().to_string();
        assert!(e.starts_with(&format!("cannot create the folder {}: ", file.join("sub").display())), "{e}");
        create_folder(&dir.path().join("x").join("y")).unwrap();
        assert!(dir.path().join("x").join("y").is_dir());
    }

    #[test]
    fn ppm_round_trip_and_bad_files_named() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.ppm");
        let bytes: Vec<u8> = (0..2 * 3 * 3).map(|i| i as u8 * 10).collect();
        write_rgb8(&path, 2, 3, &bytes).unwrap();
        assert_eq!(read_ppm(&path).unwrap(), (2, 3, bytes.clone()));
        std::fs::write(&path, b"P6\n2 x\n255\n").unwrap();
        assert_eq!(read_ppm(&path).unwrap_err().to_string(), format!("{}: not an 8-bit P6 PPM", path.display()));
        std::fs::write(&path, [b"P6\n2 3\n255\n".as_slice(), &bytes[1..]].concat()).unwrap();
        assert_eq!(read_ppm(&path).unwrap_err().to_string(), format!("{}: expected 18 bytes of pixels, found 17", path.display()));
        let gone = dir.path().join("gone.ppm");
        assert!(read_ppm(&gone).unwrap_err().to_string().starts_with(&format!("cannot read {}: ", gone.display())));
    }
}
