//! Reading a model file (`.bpt` Bezier patches or a NURBS `.json` surface) into owned storage
//! and baking its hierarchy into `Vec`s, for host programs: the examples, and host-tests
//! (which include this file).

use spline_tess::bake::{
    bake_hierarchy_with, BakeBuffers, BakeError, BakeProgress, BakeScratch, BakeSettings, Parallel,
};
use spline_tess::host::{Mesh, Surfaces};
use spline_tess::tessellator::{Hierarchy, HierarchyNode, HierarchyPatch, HierarchyVertex};
use spline_tess::{BoundaryCurve, EdgeLink, Model, ParamRect, PatchHeader, PatchSet};

/// A model's patches in owned storage. A NURBS surface is decomposed into its rational Bezier
/// pieces; `domains[k]` is piece `k`'s rectangle of the surface's parameters.
#[derive(Debug, Clone)]
pub struct ModelFile {
    /// Patch headers.
    pub headers: Vec<PatchHeader>,
    /// Control points.
    pub points: Vec<[f32; 3]>,
    /// Weights (NURBS pieces only).
    pub weights: Option<Vec<f32>>,
    /// Each patch's parameter rectangle in the file's own parameters (the unit square for BPT).
    pub domains: Vec<ParamRect>,
}

impl ModelFile {
    /// Reads `path`: NURBS JSON when its text starts with `{`, BPT otherwise
    /// ([`Surfaces::read`]).
    pub fn read(path: &str) -> Result<Self, String> {
        Surfaces::read(path)
            .map(ModelFile::from)
            .map_err(|e| format!("{path}: {e}"))
    }

    /// Parses BPT text.
    pub fn from_bpt(text: &str) -> Result<Self, String> {
        Surfaces::from_bpt(text)
            .map(ModelFile::from)
            .map_err(|e| e.to_string())
    }

    /// Parses NURBS JSON text and decomposes the surface into rational Bezier patches.
    pub fn from_nurbs_json(text: &str) -> Result<Self, String> {
        Surfaces::from_nurbs_json(text)
            .map(ModelFile::from)
            .map_err(|e| e.to_string())
    }

    /// The model as the crate's host API holds it.
    pub fn surfaces(&self) -> Surfaces {
        Surfaces::from_parts(
            self.headers.clone(),
            self.points.clone(),
            self.weights.clone(),
            Some(self.domains.clone()),
        )
        .expect("a model file's patches make surfaces")
    }

    /// The patches.
    pub fn patches(&self) -> PatchSet<'_> {
        PatchSet::new(&self.headers, &self.points, self.weights.as_deref())
            .expect("a parsed model is a valid patch set")
    }

    /// Builds the topology and runs `f` on the model.
    pub fn with_model<R>(&self, f: impl FnOnce(&Model<'_>) -> R) -> Result<R, String> {
        let patches = self.patches();
        let mut edges = vec![[EdgeLink::Collapsed; 4]; patches.len()];
        let mut curves = vec![BoundaryCurve::default(); 4 * patches.len()];
        let model = Model::build(patches, &mut edges, &mut curves).map_err(|e| e.to_string())?;
        Ok(f(&model))
    }
}

impl From<Surfaces> for ModelFile {
    fn from(s: Surfaces) -> Self {
        ModelFile {
            headers: s.headers().to_vec(),
            points: s.points().to_vec(),
            weights: s.weights().map(<[f32]>::to_vec),
            domains: s.domains().to_vec(),
        }
    }
}

/// Writes `mesh` as OBJ ([`Mesh::write_obj`]) to `path`, creating its folder.
pub fn write_obj(path: &str, mesh: &Mesh) -> Result<(), String> {
    if let Some(dir) = std::path::Path::new(path).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        }
    }
    let file = std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?;
    mesh.write_obj(&mut std::io::BufWriter::new(file))
        .map_err(|e| format!("{path}: {e}"))
}

/// The rectangle `inner` of `outer`'s unit square, as a rectangle of what `outer` is in.
pub fn within(outer: ParamRect, inner: ParamRect) -> ParamRect {
    let (du, dv) = (outer.u1 - outer.u0, outer.v1 - outer.v0);
    ParamRect {
        u0: outer.u0 + inner.u0 * du,
        u1: outer.u0 + inner.u1 * du,
        v0: outer.v0 + inner.v0 * dv,
        v1: outer.v0 + inner.v1 * dv,
    }
}

impl ModelFile {
    /// Every patch split into four ([`PatchSet::split`]): quarter `k` is a part of patch
    /// `k / 4`, and the second value holds its rectangle of that patch's unit square.
    pub fn split(&self) -> Result<(ModelFile, Vec<ParamRect>), String> {
        let set = self.patches();
        let n = set.split_size();
        let mut headers = vec![PatchHeader::default(); n.patches];
        let mut points = vec![[0.0; 3]; n.points];
        let mut weights = vec![0.0; n.points];
        let mut local = vec![ParamRect::default(); n.patches];
        set.split(&mut headers, &mut points, &mut weights, &mut local)
            .map_err(|e| e.to_string())?;
        let domains = local
            .iter()
            .enumerate()
            .map(|(k, &r)| within(self.domains[k / 4], r))
            .collect();
        let file = ModelFile {
            headers,
            points,
            weights: self.weights.as_ref().map(|_| weights),
            domains,
        };
        Ok((file, local))
    }
}

/// A model's hierarchy (`spline_tess::bake`) in `Vec`s, with the model it was baked from.
#[derive(Clone, Debug)]
pub struct BakedHierarchy {
    /// The model.
    pub file: ModelFile,
    /// Nodes.
    pub nodes: Vec<HierarchyNode>,
    /// Vertices.
    pub vertices: Vec<HierarchyVertex>,
    /// Patch records.
    pub patches: Vec<HierarchyPatch>,
}

impl BakedHierarchy {
    /// Bakes `file` with `settings`, growing the buffers until they fit.
    pub fn bake(file: &ModelFile, settings: &BakeSettings) -> Result<Self, String> {
        Self::bake_with_progress(file, settings, &mut |_| {})
    }

    /// [`bake`](Self::bake), handing `progress` how far it has come (a bake that outgrows its
    /// buffers starts again in larger ones: the count starts again too).
    pub fn bake_with_progress(
        file: &ModelFile,
        settings: &BakeSettings,
        progress: &mut dyn FnMut(BakeProgress),
    ) -> Result<Self, String> {
        let count = file.patches().len();
        // Large enough for the repository's models at 2.5e-4 of their diagonal in one pass.
        let (mut nodes, mut vertices) = (1usize << 18, 1usize << 17);
        loop {
            let mut n = vec![HierarchyNode::default(); nodes];
            let mut v = vec![HierarchyVertex::default(); vertices];
            let mut p = vec![HierarchyPatch::default(); count];
            let mut s = vec![BakeScratch::default(); nodes];
            let result = file.with_model(|m| {
                bake_hierarchy_with(
                    m,
                    settings,
                    BakeBuffers {
                        nodes: &mut n,
                        vertices: &mut v,
                        patches: &mut p,
                        scratch: &mut s,
                    },
                    progress,
                    &Parallel,
                )
            })?;
            match result {
                Ok(size) => {
                    n.truncate(size.nodes);
                    v.truncate(size.vertices);
                    return Ok(BakedHierarchy {
                        file: file.clone(),
                        nodes: n,
                        vertices: v,
                        patches: p,
                    });
                }
                Err(BakeError::NodesFull { .. }) => nodes *= 2,
                Err(BakeError::VerticesFull { .. }) => vertices *= 2,
                Err(e) => return Err(e.to_string()),
            }
        }
    }

    /// Whether the records hold together ([`Hierarchy::new`]).
    pub fn check(&self) -> Result<(), String> {
        Hierarchy::new(
            self.file.patches(),
            &self.nodes,
            &self.vertices,
            &self.patches,
        )
        .map(|_| ())
        .map_err(|e| format!("hierarchy: {e}"))
    }

    /// The checked hierarchy.
    pub fn tree(&self) -> Hierarchy<'_> {
        Hierarchy::new(
            self.file.patches(),
            &self.nodes,
            &self.vertices,
            &self.patches,
        )
        .expect("a fresh bake checks")
    }

    /// The checked hierarchy with its links (`Hierarchy::with_links`), filled into `links`:
    /// what a host's frames read.
    pub fn linked_tree<'a>(
        &'a self,
        links: &'a mut Vec<spline_tess::tessellator::NodeLink>,
    ) -> Hierarchy<'a> {
        let tree = self.tree();
        links.clear();
        links.resize(tree.link_slots(), Default::default());
        tree.fill_links(links).expect("room for every node");
        let links: &'a [_] = links;
        tree.with_links(links).expect("its own links")
    }

    /// The hierarchy's compact bytes ([`encode_hierarchy`](spline_tess::bake::encode_hierarchy)).
    pub fn encoded(&self) -> Vec<u8> {
        let tree = self.tree();
        let mut scratch =
            vec![
                0u32;
                spline_tess::bake::encode_scratch_len(self.nodes.len(), self.vertices.len())
            ];
        let mut out =
            vec![0u8; 64 + 64 * (self.nodes.len() + self.vertices.len() + self.patches.len())];
        let len = spline_tess::bake::encode_hierarchy(&tree, &mut scratch, &mut out)
            .expect("a fresh bake encodes");
        out.truncate(len);
        out
    }

    /// The hierarchy read from its compact bytes `bytes` ([`encoded`](Self::encoded)).
    pub fn tree_from<'a>(&'a self, bytes: &'a [u8]) -> Hierarchy<'a> {
        Hierarchy::from_bytes(self.file.patches(), bytes).expect("fresh bytes read")
    }

    /// Bytes the records take in memory (nodes, vertices, patches).
    pub fn bytes(&self) -> usize {
        std::mem::size_of_val(self.nodes.as_slice())
            + std::mem::size_of_val(self.vertices.as_slice())
            + std::mem::size_of_val(self.patches.as_slice())
    }
}
