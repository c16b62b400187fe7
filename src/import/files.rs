//! Reading one input file whole. Only regular files are read: a device or FIFO (a path linked
//! to `/dev/zero`, a pipe) has no end, so reading it would take every byte of memory. Every
//! input file of a run is read here: scenes and their resources, photometric files, targets,
//! probe and design tables.

use std::io::{Error, ErrorKind};
use std::path::Path;

/// The bytes of the regular file at `path` (symbolic links followed); anything else is an error
/// saying what it is.
pub fn read(path: &Path) -> std::io::Result<Vec<u8>> {
    let kind = std::fs::metadata(path)?.file_type();
    if !kind.is_file() {
        let what = match kind.is_dir() {
            true => "a folder",
            false => "a device, FIFO or socket",
        };
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("{what}, not a regular file"),
        ));
    }
    std::fs::read(path)
}

/// [`read`] as UTF-8 text (a leading byte-order mark kept: parsers skip it where they allow it).
pub fn read_text(path: &Path) -> std::io::Result<String> {
    String::from_utf8(read(path)?)
        .map_err(|_| Error::new(ErrorKind::InvalidData, "stream did not contain valid UTF-8"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regular_files_are_read_and_devices_and_folders_refused() {
        let dir = std::env::temp_dir().join(format!("luxbake-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a.txt");
        std::fs::write(&file, "lx").unwrap();
        assert_eq!(read_text(&file).unwrap(), "lx");
        let e = read(Path::new("/dev/zero")).unwrap_err();
        assert!(e.to_string().contains("device, FIFO or socket"), "{e}");
        let e = read(&dir).unwrap_err();
        assert!(e.to_string().contains("a folder"), "{e}");
        std::fs::write(&file, [0xff, 0xfe]).unwrap();
        assert_eq!(read_text(&file).unwrap_err().kind(), ErrorKind::InvalidData);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
