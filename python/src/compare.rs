//! `tmc.compare`: the figures of `tmc compare --json` for an array or a
//! path, from the library's [`tmc::compare::compare`] (the CLI's steps 1
//! to 3: timed pairs, the survey of differing cells, each mesh's topology).

use crate::array::MappedAt;
use crate::extract::{params, preflight, Input, Select};
use pyo3::prelude::*;
use serde_json::json;

/// Times TMC against MC on `input` (`runs` interleaved pairs after a
/// warm-up, nothing written), surveys the cells they triangulate
/// differently and checks each mesh's topology unless the meshes would
/// need more than `topology_memory` bytes (2 GiB by default). Returns the
/// JSON text of `tmc compare --json`'s figures (without the CLI's peak
/// memory).
#[pyfunction]
#[pyo3(signature = (input, iso, spacing, origin, mapped, inside, close, threads, select, runs, topology_memory = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn compare(
    py: Python<'_>,
    input: &Bound<'_, PyAny>,
    iso: f64,
    spacing: [f64; 3],
    origin: [f64; 3],
    mapped: MappedAt,
    inside: &str,
    close: bool,
    threads: usize,
    select: Select,
    runs: usize,
    topology_memory: Option<u64>,
) -> PyResult<String> {
    let params = params(iso, "tmc", inside, close, threads, false)?;
    let input = Input::new(input, spacing, origin, mapped, select)?;
    let limit = topology_memory.unwrap_or(tmc::compare::TOPOLOGY_MEMORY);
    input.run(py, None, |source, path, watch| {
        let options = preflight(source, path, &params, None, watch)?;
        let hooks = tmc::compare::Hooks::default();
        let found = tmc::compare::compare(source, &params, runs, limit, &options, hooks)?;
        let note = found.topology_left_out.map(|most| {
            format!(
                "components, Euler characteristic and genus left out: they hold the mesh \
                 in memory, about {most} bytes, over topology_memory {limit}"
            )
        });
        let mut map = found.json();
        map.insert("input".into(), json!(path.map(|p| p.display().to_string())));
        map.insert("topology_note".into(), json!(note));
        Ok(serde_json::Value::Object(map).to_string())
    })
}
