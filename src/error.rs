//! Typed errors of the library. Every error names the file and, where there is one, the element
//! inside it (a glTF JSON pointer such as `/materials/3`), so the CLI can print one clear line.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The input could not be read or parsed, or holds a value the bake cannot accept.
    #[error("{file}: {}{message}", fmt_at(.at))]
    Input {
        file: PathBuf,
        /// JSON pointer (`/materials/3`) or other locator; empty when it concerns the whole file.
        at: String,
        message: String,
    },
    /// Settings given on the command line (or through the API) are invalid.
    #[error("invalid setting: {0}")]
    Settings(String),
    /// The output could not be written.
    #[error("{file}: {message}")]
    Output { file: PathBuf, message: String },
    /// Something inside the bake failed (a bug or a numerical breakdown).
    #[error("bake failed: {0}")]
    Bake(String),
}

fn fmt_at(at: &str) -> String {
    if at.is_empty() {
        String::new()
    } else {
        format!("{at}: ")
    }
}

impl Error {
    pub fn input(
        file: impl Into<PathBuf>,
        at: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Error::Input {
            file: file.into(),
            at: at.into(),
            message: message.into(),
        }
    }

    pub fn output(file: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::Output {
            file: file.into(),
            message: message.into(),
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
