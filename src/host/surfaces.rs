//! A model's surfaces in owned storage, read from a file or bytes.

use std::path::Path;
use std::vec;
use std::vec::Vec;

use super::{Baked, HostError};
use crate::bake::BakeSettings;
use crate::parse::{self, NurbsJsonBuffers};
use crate::{BoundaryCurve, EdgeLink, Model, ParamRect, PatchHeader, PatchSet};

/// A model's surfaces in owned storage: rational Bezier patches, from BPT text, or from a
/// NURBS surface's JSON decomposed into its Bezier pieces.
#[derive(Clone, Debug, PartialEq)]
pub struct Surfaces {
    headers: Vec<PatchHeader>,
    points: Vec<[f32; 3]>,
    weights: Option<Vec<f32>>,
    /// Each patch's rectangle of the file's own parameters: the unit square for BPT, the
    /// knot span of a NURBS piece.
    domains: Vec<ParamRect>,
}

/// The unit square.
const UNIT: ParamRect = ParamRect {
    u0: 0.0,
    u1: 1.0,
    v0: 0.0,
    v1: 1.0,
};

impl Surfaces {
    /// Reads a model file: NURBS JSON when its text starts with `{`, BPT otherwise.
    pub fn read(path: impl AsRef<Path>) -> Result<Surfaces, HostError> {
        Surfaces::from_bytes(&std::fs::read(path)?)
    }

    /// A model file's bytes: NURBS JSON when its text starts with `{`, BPT otherwise.
    pub fn from_bytes(bytes: &[u8]) -> Result<Surfaces, HostError> {
        let text = core::str::from_utf8(bytes).map_err(|_| HostError::NotText)?;
        if text.trim_start().starts_with('{') {
            Surfaces::from_nurbs_json(text)
        } else {
            Surfaces::from_bpt(text)
        }
    }

    /// Parses BPT text (see [`parse::parse_bpt`]).
    pub fn from_bpt(text: &str) -> Result<Surfaces, HostError> {
        let size = parse::bpt_size(text)?;
        let mut headers = vec![PatchHeader::default(); size.patches];
        let mut points = vec![[0.0; 3]; size.points];
        parse::parse_bpt(text, &mut headers, &mut points)?;
        let surfaces = Surfaces {
            domains: vec![UNIT; headers.len()],
            headers,
            points,
            weights: None,
        };
        surfaces.with_model(|_| ())?;
        Ok(surfaces)
    }

    /// Parses a NURBS surface's JSON (see [`parse::parse_nurbs_json`]) and decomposes it
    /// into rational Bezier patches.
    pub fn from_nurbs_json(text: &str) -> Result<Surfaces, HostError> {
        let size = parse::nurbs_json_size(text)?;
        let mut knots_u = vec![0.0; size.knots_u];
        let mut knots_v = vec![0.0; size.knots_v];
        let mut net = vec![[0.0; 3]; size.points];
        let mut net_weights = vec![0.0; size.points];
        let buffers = NurbsJsonBuffers {
            knots_u: &mut knots_u,
            knots_v: &mut knots_v,
            points: &mut net,
            weights: &mut net_weights,
        };
        let surface = parse::parse_nurbs_json(text, buffers)?;
        let need = surface.decomposition_size();
        let mut headers = vec![PatchHeader::default(); need.patches];
        let mut points = vec![[0.0; 3]; need.points];
        let mut weights = vec![0.0; need.points];
        let mut domains = vec![ParamRect::default(); need.patches];
        surface.decompose(&mut headers, &mut points, &mut weights, &mut domains)?;
        let surfaces = Surfaces {
            headers,
            points,
            weights: Some(weights),
            domains,
        };
        surfaces.with_model(|_| ())?;
        Ok(surfaces)
    }

    /// Patches of one's own: their headers, control points and weights (`None`: all 1), and
    /// each one's rectangle of the parameters a [`Face`](super::Face) gives (the unit square
    /// for each: `None`), checked as [`PatchSet::new`] and [`Model::build`] check them.
    pub fn from_parts(
        headers: Vec<PatchHeader>,
        points: Vec<[f32; 3]>,
        weights: Option<Vec<f32>>,
        domains: Option<Vec<ParamRect>>,
    ) -> Result<Surfaces, HostError> {
        let surfaces = Surfaces {
            domains: domains.unwrap_or_else(|| vec![UNIT; headers.len()]),
            headers,
            points,
            weights,
        };
        if surfaces.domains.len() != surfaces.headers.len() {
            return Err(HostError::Domains {
                patches: surfaces.headers.len(),
                domains: surfaces.domains.len(),
            });
        }
        surfaces.with_model(|_| ())?;
        Ok(surfaces)
    }

    /// The patches' headers (degrees and where their control points start).
    pub fn headers(&self) -> &[PatchHeader] {
        &self.headers
    }

    /// The control points.
    pub fn points(&self) -> &[[f32; 3]] {
        &self.points
    }

    /// The control points' weights (`None`: all 1, as for BPT).
    pub fn weights(&self) -> Option<&[f32]> {
        self.weights.as_deref()
    }

    /// The patches.
    pub fn patches(&self) -> PatchSet<'_> {
        // Validated when the surfaces were read, and kept unchanged since.
        PatchSet::validated(&self.headers, &self.points, self.weights.as_deref())
    }

    /// Each patch's rectangle of the file's own parameters: the unit square for BPT, its
    /// knot span for a piece of a NURBS surface.
    pub fn domains(&self) -> &[ParamRect] {
        &self.domains
    }

    /// Builds the model (the patches with their shared curves) and hands it to `f`.
    pub fn with_model<R>(&self, f: impl FnOnce(&Model<'_>) -> R) -> Result<R, HostError> {
        let patches = PatchSet::new(&self.headers, &self.points, self.weights.as_deref())?;
        let mut edges = vec![[EdgeLink::Collapsed; 4]; patches.len()];
        let mut curves = vec![BoundaryCurve::default(); 4 * patches.len()];
        let model = Model::build(patches, &mut edges, &mut curves)?;
        Ok(f(&model))
    }

    /// Bakes the surfaces on all cores (see [`bake`](crate::bake) and
    /// [`Parallel`](crate::bake::Parallel)): the same hierarchy, bit for bit, as a bake on
    /// one.
    pub fn bake(&self, settings: &BakeSettings) -> Result<Baked, HostError> {
        Baked::bake(self, settings)
    }

    /// The bake of `settings` kept in the file `path`: read from it where it holds a bake of
    /// these surfaces with these settings (its bytes checked, see [`Baked::read_cache`]),
    /// baked and written there otherwise (to a file beside it, then renamed, so that a reader
    /// never sees half of one). A bake kept by an older version of the crate is still a sound
    /// hierarchy of the surfaces, though a fresh bake may now give other bytes.
    pub fn bake_cached(
        &self,
        settings: &BakeSettings,
        path: impl AsRef<Path>,
    ) -> Result<Baked, HostError> {
        let path = path.as_ref();
        if let Ok(bytes) = std::fs::read(path) {
            if let Some(baked) = Baked::read_cache(self, settings, &bytes) {
                return Ok(baked);
            }
        }
        let baked = self.bake(settings)?;
        let mut part = std::ffi::OsString::from(path.as_os_str());
        part.push(".part");
        std::fs::write(&part, baked.cache_bytes(settings)?)?;
        std::fs::rename(&part, path)?;
        Ok(baked)
    }
}
