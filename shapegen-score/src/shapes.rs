//! [`ShapeMeshes`]: the mesh of each of a generator's shapes.

use std::borrow::Cow;

use shapegen_core::express::Generator;

use crate::error::ScoreError;
use crate::mesh::Mesh;

/// The meshes of a generator's shapes, indexed by shape id.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ShapeMeshes {
    names: Vec<Cow<'static, str>>,
    meshes: Vec<Mesh>,
}

impl ShapeMeshes {
    /// The built-in mesh of every shape of `generator` (see [`Mesh::builtin`]);
    /// fails on a shape without a built-in mesh.
    pub fn builtin<G: Generator>(generator: &G) -> Result<Self, ScoreError> {
        let names = generator.shapes().to_vec();
        let meshes = names
            .iter()
            .map(|n| Mesh::builtin(n).ok_or_else(|| ScoreError::UnknownShape(n.to_string())))
            .collect::<Result<_, _>>()?;
        Ok(Self { names, meshes })
    }

    /// Named meshes given directly: shape `i` is `names[i]` with `meshes[i]`.
    pub fn new(names: Vec<Cow<'static, str>>, meshes: Vec<Mesh>) -> Result<Self, ScoreError> {
        if names.len() != meshes.len() {
            return Err(ScoreError::Target(format!(
                "{} shape names for {} meshes",
                names.len(),
                meshes.len()
            )));
        }
        Ok(Self { names, meshes })
    }

    /// Replaces the mesh of shape `name` (e.g. by one loaded from a file).
    pub fn set(&mut self, name: &str, mesh: Mesh) -> Result<(), ScoreError> {
        let i = self
            .names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| ScoreError::UnknownShape(name.to_string()))?;
        self.meshes[i] = mesh;
        Ok(())
    }

    /// Checks that these are the meshes of the shapes `names` (a
    /// generator's, in its order).
    pub fn check_for(&self, names: &[Cow<'static, str>]) -> Result<(), ScoreError> {
        if self.names.as_slice() == names {
            return Ok(());
        }
        Err(ScoreError::Target(format!(
            "the meshes are for shapes [{}], the generator emits [{}]",
            self.names.join(", "),
            names.join(", ")
        )))
    }

    /// Number of shapes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.meshes.len()
    }

    /// Whether there are no shapes.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.meshes.is_empty()
    }

    /// The mesh of shape `id`.
    #[must_use]
    pub fn mesh(&self, id: u16) -> &Mesh {
        &self.meshes[id as usize]
    }

    /// The name of shape `id`.
    #[must_use]
    pub fn name(&self, id: u16) -> &str {
        &self.names[id as usize]
    }
}
