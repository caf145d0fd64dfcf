//! The model files shipped with the app (`models/`): which they are, and their bytes.
//!
//! The command line and the native tests have every file built in. The page does not: its wasm
//! would carry 6 MB of weights every visitor downloads whether or not a method ever uses them.
//! There the files are served beside the page (`dist/models/`, precached by the service worker
//! for offline use) and a method that needs one it does not hold yet fails with
//! [`MethodError::NeedsModel`]; the page fetches the file (showing its progress), hands it to
//! its worker ([`super::ModelStore::provide`]) and runs the method again. Every file handed over is checked
//! against the SHA-256 `build.rs` recorded when this build was made, so a stale or damaged file
//! from a server or a cache is refused with a message rather than used.
//!
//! The files handed over and the models read from them belong to whoever runs — the page's worker, a command-line
//! run, a test — through its [`super::ModelStore`] ([`Shipped`]): nothing here is process-wide.

use std::any::Any;
use std::sync::Arc;

use sha2::{Digest, Sha256};

use super::MethodError;

/// A shipped model file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShippedFile {
    /// Its name in `models/` (and in the page's `models/` folder).
    pub file: &'static str,
    /// The SHA-256 of its bytes (lowercase hex).
    pub sha256: &'static str,
    /// Its size in bytes.
    pub size: u64,
}

include!(concat!(env!("OUT_DIR"), "/shipped_models.rs"));

/// The shipped file called `file`, or a message listing them.
pub fn find(file: &str) -> Result<(usize, &'static ShippedFile), String> {
    FILES.iter().enumerate().find(|(_, f)| f.file == file).ok_or_else(|| {
        format!(
            "`{file}` is not a shipped model file; shipped: {}",
            FILES.iter().map(|f| f.file).collect::<Vec<_>>().join(", ")
        )
    })
}

/// A shipped file's bytes: built in, or the copy handed over.
#[derive(Clone, Debug)]
pub enum FileBytes {
    #[cfg_attr(not(embedded_models), allow(dead_code))]
    BuiltIn(&'static [u8]),
    #[cfg_attr(embedded_models, allow(dead_code))]
    Given(Arc<[u8]>),
}

impl std::ops::Deref for FileBytes {
    type Target = [u8];
    fn deref(&self) -> &[u8] {
        match self {
            FileBytes::BuiltIn(b) => b,
            FileBytes::Given(b) => b,
        }
    }
}

/// The files handed over with [`Shipped::provide`] where they are not built in (the page's worker: at most one copy
/// of each of a handful of files), and the files the page could not give (damaged, or not fetched:
/// [`Shipped::refuse`]) with why, so that a run asks for them no more: it fails with that message where it needs the
/// file, and goes on without it where the file was only one of several it could use (the models a take fit offers
/// instead).
#[cfg_attr(embedded_models, allow(dead_code))]
#[derive(Default)]
struct Provided(Vec<(usize, Arc<[u8]>)>, Vec<(usize, String)>);

#[cfg_attr(embedded_models, allow(dead_code))]
impl Provided {
    fn get(&self, file: &str) -> Result<FileBytes, MethodError> {
        let (index, _) = find(file).map_err(MethodError::Failed)?;
        if let Some((_, b)) = self.0.iter().find(|(i, _)| *i == index) {
            return Ok(FileBytes::Given(b.clone()));
        }
        match self.1.iter().find(|(i, _)| *i == index) {
            Some((_, why)) => Err(MethodError::Failed(why.clone())),
            None => Err(MethodError::NeedsModel { file: file.to_string() }),
        }
    }

    fn add(&mut self, file: &str, bytes: Vec<u8>) -> Result<(), String> {
        let (index, shipped) = find(file)?;
        if let Err(why) = check(shipped, &bytes) {
            self.refuse(index, why.clone());
            return Err(why);
        }
        self.1.retain(|(i, _)| *i != index);
        if !self.0.iter().any(|(i, _)| *i == index) {
            self.0.push((index, bytes.into()));
        }
        Ok(())
    }

    /// Remembers why file `index` cannot be had (a good copy held already stays).
    fn refuse(&mut self, index: usize, why: String) {
        if !self.0.iter().any(|(i, _)| *i == index) {
            self.1.retain(|(i, _)| *i != index);
            self.1.push((index, why));
        }
    }
}

/// The shipped files one runner holds and the models it read from them, each read once ([`Shipped::read`]). A
/// [`super::ModelStore`] owns one.
#[derive(Default)]
pub struct Shipped {
    #[cfg_attr(embedded_models, allow(dead_code))]
    given: Provided,
    read: Vec<(usize, Arc<dyn Any + Send + Sync>)>,
}

impl Shipped {
    /// The bytes of the shipped file `file`: built in, or handed over with [`Shipped::provide`]; else
    /// [`MethodError::NeedsModel`] (only on the page).
    pub fn bytes(&self, file: &str) -> Result<FileBytes, MethodError> {
        #[cfg(embedded_models)]
        {
            let (index, _) = find(file).map_err(MethodError::Failed)?;
            Ok(FileBytes::BuiltIn(EMBEDDED[index]))
        }
        #[cfg(not(embedded_models))]
        {
            self.given.get(file)
        }
    }

    /// Hands over the bytes of the shipped file `file` (fetched by the page). Refused, naming the file, when it is
    /// not a shipped file or its bytes are not this build's (another size or SHA-256). Where the files are built in,
    /// the bytes are only checked. Handing a file over again keeps the first copy.
    pub fn provide(&mut self, file: &str, bytes: Vec<u8>) -> Result<(), String> {
        #[cfg(embedded_models)]
        {
            let (_, shipped) = find(file)?;
            check(shipped, &bytes)
        }
        #[cfg(not(embedded_models))]
        {
            self.given.add(file, bytes)
        }
    }

    /// The page could not get the shipped file `file` (`why`: the fetch's error): a run that needs it fails with
    /// `why` instead of asking for it again, and one that could do without it goes on. Where the files are built in,
    /// nothing changes.
    pub fn refuse(&mut self, file: &str, why: String) -> Result<(), String> {
        let (_index, _) = find(file)?;
        #[cfg(not(embedded_models))]
        self.given.refuse(_index, why);
        #[cfg(embedded_models)]
        drop(why);
        Ok(())
    }

    /// The model read from `file` earlier, if it was read as a `T`.
    pub fn read<T: Any + Send + Sync>(&self, file: &str) -> Option<Arc<T>> {
        let (index, _) = find(file).ok()?;
        self.read.iter().find(|(i, _)| *i == index).and_then(|(_, m)| m.clone().downcast::<T>().ok())
    }

    /// Keeps `model`, read from `file`, for the next [`Shipped::read`].
    pub fn keep<T: Any + Send + Sync>(&mut self, file: &str, model: Arc<T>) {
        if let Ok((index, _)) = find(file) {
            self.read.retain(|(i, _)| *i != index);
            self.read.push((index, model));
        }
    }
}

/// Checks `bytes` against what this build recorded of `shipped`.
fn check(shipped: &ShippedFile, bytes: &[u8]) -> Result<(), String> {
    let name = shipped.file;
    if bytes.len() as u64 != shipped.size {
        return Err(format!(
            "models/{name}: {} bytes where this build's file has {}: the server or a cache gave another version (reload the page)",
            bytes.len(),
            shipped.size
        ));
    }
    let sha: String = Sha256::digest(bytes).iter().map(|b| format!("{b:02x}")).collect();
    if sha != shipped.sha256 {
        return Err(format!(
            "models/{name}: its SHA-256 is {sha}, not this build's {}: the file is damaged or of another version (reload the page)",
            shipped.sha256
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_file_of_models_is_listed_with_its_size_and_hash() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
        for f in FILES {
            let on_disk = std::fs::read(dir.join(f.file)).unwrap();
            assert_eq!(on_disk.len() as u64, f.size, "{}", f.file);
            check(f, &on_disk).unwrap();
            let held = Shipped::default().bytes(f.file).unwrap();
            assert_eq!(&*held, &on_disk[..], "{}: the built-in bytes are the file's", f.file);
        }
        let names: Vec<&str> = FILES.iter().map(|f| f.file).collect();
        for expected in ["dtfcn-exercises.model", "knn-locomotion.model", "lma-effort.json"] {
            assert!(names.contains(&expected), "{expected} in {names:?}");
        }
    }

    #[test]
    fn another_version_of_a_file_is_refused_naming_it() {
        let f = &FILES[0];
        let mut bytes =
            std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models").join(f.file)).unwrap();
        bytes[100] ^= 1;
        let mut store = Shipped::default();
        let err = store.provide(f.file, bytes.clone()).unwrap_err();
        assert!(err.contains(f.file) && err.contains("SHA-256"), "{err}");
        bytes.pop();
        let err = store.provide(f.file, bytes).unwrap_err();
        assert!(err.contains("bytes where this build's file has"), "{err}");
        let err = store.provide("nope.model", vec![]).unwrap_err();
        assert!(err.contains("not a shipped model file") && err.contains("lma-effort.json"), "{err}");
        assert!(matches!(store.bytes("nope.model"), Err(MethodError::Failed(_))));
    }

    /// Where the files are not built in (the page's worker): a file is missing until handed
    /// over, a damaged one is refused and then fails with why (it is not asked for again) until
    /// a good copy comes, and the first good copy is kept.
    #[test]
    fn a_file_not_built_in_is_needed_until_handed_over() {
        let f = &FILES[FILES.len() - 1];
        let good = std::fs::read(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models").join(f.file)).unwrap();
        let mut store = Provided::default();
        match store.get(f.file) {
            Err(MethodError::NeedsModel { file }) => assert_eq!(file, f.file),
            other => panic!("{other:?}"),
        }
        let mut bad = good.clone();
        bad[0] ^= 0xff;
        let why = store.add(f.file, bad).unwrap_err();
        match store.get(f.file) {
            Err(MethodError::Failed(said)) => assert_eq!(said, why, "the refusal, not a request for the file"),
            other => panic!("{other:?}"),
        }
        // a file the page could not fetch: the same
        let (other, _) = find(FILES[0].file).unwrap();
        store.refuse(other, "could not fetch the model models/x: HTTP 404".into());
        assert!(matches!(store.get(FILES[0].file), Err(MethodError::Failed(m)) if m.ends_with("HTTP 404")));
        store.add(f.file, good.clone()).unwrap();
        store.add(f.file, good.clone()).unwrap();
        assert_eq!(store.0.len(), 1, "one copy");
        assert_eq!(&*store.get(f.file).unwrap(), &good[..]);
        assert!(matches!(store.get(FILES[1].file), Err(MethodError::NeedsModel { .. })), "the others still missing");
        // a good copy clears a refusal; a refusal after it changes nothing
        store.refuse(store.0[0].0, "late".into());
        assert_eq!(&*store.get(f.file).unwrap(), &good[..]);
    }

    /// What a store read from a file is its own: another store reads it again, a second ask of the same store gets
    /// the same model.
    #[test]
    fn models_read_are_kept_by_their_store_alone() {
        let (mut a, b) = (Shipped::default(), Shipped::default());
        let file = FILES[0].file;
        assert!(a.read::<String>(file).is_none());
        a.keep(file, Arc::new("read".to_string()));
        assert_eq!(a.read::<String>(file).as_deref().map(String::as_str), Some("read"));
        assert!(a.read::<u32>(file).is_none(), "read as another type");
        assert!(b.read::<String>(file).is_none(), "another store holds its own");
    }
}
