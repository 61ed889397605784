//! Files under the output directory: atomic writes and where each artefact lives.
use crate::{MethodId, StudyError};
use std::path::{Path, PathBuf};

/// `DIR/csv/metrics.csv`.
pub fn metrics_csv(dir: &Path) -> PathBuf {
    dir.join("csv").join("metrics.csv")
}

/// `DIR/csv/failures.csv`.
pub fn failures_csv(dir: &Path) -> PathBuf {
    dir.join("csv").join("failures.csv")
}

/// `DIR/csv/shard.csv`: which shard of which job list a sharded run ran.
pub fn shard_csv(dir: &Path) -> PathBuf {
    dir.join("csv").join("shard.csv")
}

/// `DIR/tables/table_NN.md`.
pub fn table_md(dir: &Path, number: u8) -> PathBuf {
    dir.join("tables").join(format!("table_{number:02}.md"))
}

/// `DIR/summary.md`.
pub fn summary_md(dir: &Path) -> PathBuf {
    dir.join("summary.md")
}

/// `DIR/fidelity.md`.
pub fn fidelity_md(dir: &Path) -> PathBuf {
    dir.join("fidelity.md")
}

/// `DIR/csv/fidelity.csv`.
pub fn fidelity_csv(dir: &Path) -> PathBuf {
    dir.join("csv").join("fidelity.csv")
}

/// `DIR/csv/significance.csv`.
pub fn significance_csv(dir: &Path) -> PathBuf {
    dir.join("csv").join("significance.csv")
}

/// `DIR/figures/fig_N.png`.
pub fn figure_png(dir: &Path, n: u8) -> PathBuf {
    dir.join("figures").join(format!("fig_{n}.png"))
}

/// `DIR/figures/meshes/REGION_K<K>_METHOD.png`.
pub fn mesh_png(dir: &Path, region: &str, k: usize, method: MethodId) -> PathBuf {
    dir.join("figures")
        .join("meshes")
        .join(format!("{region}_K{k}_{}.png", method.name()))
}

/// `DIR/meshes/REGION_K<K>_METHOD_seed<S>` (Triangle `.node`/`.ele`/`.poly` beside it).
pub fn mesh_base(dir: &Path, region: &str, k: usize, method: MethodId, seed: u64) -> PathBuf {
    dir.join("meshes")
        .join(format!("{region}_K{k}_{}_seed{seed}", method.name()))
}

/// The `.node` file of [`mesh_base`].
pub fn mesh_node(dir: &Path, region: &str, k: usize, method: MethodId, seed: u64) -> PathBuf {
    let mut p = mesh_base(dir, region, k, method, seed).into_os_string();
    p.push(".node");
    PathBuf::from(p)
}

/// Write `bytes` to `path` through a temporary file in the same directory and a rename, so
/// a reader never sees a partial file. Parent directories are created.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), StudyError> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir).map_err(|e| StudyError::io(dir, e))?;
    cvtmesh::io::write_atomic(path, bytes).map_err(|e| StudyError::io(path, e))
}

/// Remove `path` if it is there.
pub fn remove_if_present(path: &Path) -> Result<(), StudyError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(StudyError::io(path, e)),
        _ => Ok(()),
    }
}

/// Create a directory and its parents.
pub fn create_dir(dir: &Path) -> Result<(), StudyError> {
    std::fs::create_dir_all(dir).map_err(|e| StudyError::io(dir, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_creates_dirs_replaces_and_leaves_no_temp_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a").join("b").join("x.csv");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"two");
        let names: Vec<String> = std::fs::read_dir(p.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, vec!["x.csv".to_string()]);
        // A path that cannot be written is an error, not a panic.
        assert!(write_atomic(&p.join("under_a_file"), b"x").is_err());
    }

    #[test]
    fn artefact_paths() {
        let d = Path::new("out");
        assert_eq!(table_md(d, 2), Path::new("out/tables/table_02.md"));
        assert_eq!(figure_png(d, 3), Path::new("out/figures/fig_3.png"));
        assert_eq!(
            mesh_png(d, "circle", 88, MethodId::CcvtFast),
            Path::new("out/figures/meshes/circle_K88_ccvt.png")
        );
        assert_eq!(
            mesh_node(d, "lake", 1109, MethodId::Triangle, 2),
            Path::new("out/meshes/lake_K1109_refine_seed2.node")
        );
    }
}
