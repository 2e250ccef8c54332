//! The meshes of the generator's shapes: `[shapes.NAME]` replacements,
//! else the built-in mesh of that name.

use std::borrow::Cow;

use super::Ctx;
use crate::experiment::ExperimentError;
use crate::experiment::file::ExperimentFile;
use crate::score::{Mesh, ShapeMeshes};

/// One mesh per shape of the generator (`names`, in its order).
pub(super) fn from_file(
    ctx: &Ctx<'_>,
    f: &ExperimentFile,
    names: &[Cow<'static, str>],
) -> Result<ShapeMeshes, ExperimentError> {
    for (name, s) in &f.shapes {
        if !names.iter().any(|n| n == name) {
            return Err(ctx.err(
                &format!("shapes.{name}"),
                &s.mesh,
                format!(
                    "the generator has no shape `{name}` (its shapes: {})",
                    names.join(", ")
                ),
            ));
        }
    }
    let mut meshes = Vec::with_capacity(names.len());
    for name in names {
        let mesh = match f.shapes.get(name.as_ref()) {
            Some(s) => {
                let key = format!("shapes.{name}.mesh");
                let path = ctx.path(&key, &s.mesh)?;
                let mesh =
                    Mesh::load_obj(&path).map_err(|e| ctx.err(&key, &s.mesh, e.to_string()))?;
                if s.normalize { mesh.normalized() } else { mesh }
            }
            None => Mesh::builtin(name).ok_or_else(|| {
                ctx.err(
                    "generator",
                    &f.generator,
                    format!(
                        "shape `{name}` has no built-in mesh (those are cube, frustum, trunk and leaf): give it one with\n[shapes.{name}]\nmesh = \"{name}.obj\""
                    ),
                )
            })?,
        };
        meshes.push(mesh);
    }
    Ok(ShapeMeshes::new(names.to_vec(), meshes)?)
}
