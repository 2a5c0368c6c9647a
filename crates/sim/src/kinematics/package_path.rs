//! Resolution of mesh file names found in URDF files, without ROS.
//!
//! URDF files name meshes as `package://PKG/rest`, `file:///abs/path`, absolute paths or
//! paths relative to the URDF file. ROS resolves `package://` with `rospack`; here a list
//! of search directories stands in for the ROS package path: `package://PKG/rest` is
//! found as `DIR/PKG/rest` for the first search directory `DIR` that holds it, and, as a
//! convenience for a package checked out on its own, as `DIR/rest` when `DIR` is itself
//! named `PKG`. The URDF file's own directory and its ancestors are searched last, so a
//! description kept inside its package (`PKG/urdf/robot.urdf`) resolves with no set-up.

use std::path::{Path, PathBuf};

/// Directories searched for `package://` URIs, in order.
#[derive(Debug, Clone, Default)]
pub struct PackagePaths {
    dirs: Vec<PathBuf>,
}

impl PackagePaths {
    /// Search the given directories, in order.
    pub fn new(dirs: impl IntoIterator<Item = PathBuf>) -> Self {
        Self {
            dirs: dirs.into_iter().collect(),
        }
    }

    /// The configured search directories.
    pub fn dirs(&self) -> &[PathBuf] {
        &self.dirs
    }

    /// The file a URDF mesh reference points to, if it exists. `urdf_dir` is the
    /// directory of the URDF file that holds the reference.
    pub fn resolve(&self, filename: &str, urdf_dir: &Path) -> Option<PathBuf> {
        if let Some(rest) = filename.strip_prefix("package://") {
            let (package, inner) = rest.split_once('/').unwrap_or((rest, ""));
            let ancestors = urdf_dir.ancestors().map(Path::to_path_buf);
            for dir in self.dirs.iter().cloned().chain(ancestors) {
                let candidate = dir.join(package).join(inner);
                if candidate.is_file() {
                    return Some(candidate);
                }
                if dir.file_name().is_some_and(|n| n == package) && dir.join(inner).is_file() {
                    return Some(dir.join(inner));
                }
            }
            return None;
        }
        let path = Path::new(filename.strip_prefix("file://").unwrap_or(filename));
        let candidate = if path.is_absolute() {
            path.to_path_buf()
        } else {
            urdf_dir.join(path)
        };
        candidate.is_file().then_some(candidate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("whisker-pkg-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn resolves_package_uris_relative_and_file_uris() {
        let root = scratch("resolve");
        let pkg = root.join("share/ur_description");
        fs::create_dir_all(pkg.join("meshes")).unwrap();
        fs::create_dir_all(pkg.join("urdf")).unwrap();
        fs::write(pkg.join("meshes/base.stl"), "solid x\nendsolid x\n").unwrap();
        let elsewhere = scratch("resolve-elsewhere");

        let uri = "package://ur_description/meshes/base.stl";
        // From the package's own urdf/ directory: found through the ancestors.
        let found = PackagePaths::default().resolve(uri, &pkg.join("urdf"));
        assert_eq!(
            found.as_deref(),
            Some(pkg.join("meshes/base.stl").as_path())
        );
        // From elsewhere: only with a search path, either the parent or the package itself.
        assert_eq!(PackagePaths::default().resolve(uri, &elsewhere), None);
        for dir in [root.join("share"), pkg.clone()] {
            let paths = PackagePaths::new([dir]);
            assert!(paths.resolve(uri, &elsewhere).is_some());
        }
        // Relative to the URDF, and file:// absolute.
        let rel = PackagePaths::default().resolve("../meshes/base.stl", &pkg.join("urdf"));
        assert!(rel.is_some());
        let abs = format!("file://{}", pkg.join("meshes/base.stl").display());
        assert!(PackagePaths::default().resolve(&abs, &elsewhere).is_some());
        assert_eq!(PackagePaths::default().resolve("missing.stl", &pkg), None);
    }
}
