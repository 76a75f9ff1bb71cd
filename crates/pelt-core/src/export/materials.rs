//! An object's own materials, kept on its bald faces: what Pelt's Blender fur does
//! (`addon/blender/geonodes.py`: a face bald at all three corners keeps the object's material, so a
//! head's eyes stay eyes) carried into glTF. Each such material becomes a plain
//! metallic-roughness material on a skin primitive of its own, sharing the skin's vertices, with
//! no shells, fins or fur extension on it; every other face is Pelt's furred skin.

use super::names::validate_name;
use crate::error::{Num, PeltError, Result};

/// Most material slots (Blender's: a face's material index is a 16-bit integer).
pub const MAX_SLOTS: usize = 32_767;

/// One of the object's own materials, as glTF's metallic-roughness model takes it.
#[derive(Debug, Clone, PartialEq)]
pub struct OwnMaterial {
    /// The glTF material's name, 1 to 64 characters (as an object's, [`super::input::MAX_NAME_CHARS`]).
    pub name: String,
    /// Linear RGBA, each in `[0, 1]`; alpha below 1 makes the material alpha-blended.
    pub base_color: [f32; 4],
    /// `[0, 1]`.
    pub metallic: f32,
    /// `[0, 1]`.
    pub roughness: f32,
}

/// The object's material slots and the slot of each triangle.
#[derive(Debug, Clone, Copy)]
pub struct MaterialSlots<'a> {
    /// By slot; `None` for an empty slot, whose faces are Pelt's skin.
    pub slots: &'a [Option<OwnMaterial>],
    /// Per triangle of the mesh, its slot (an index into `slots`).
    pub triangle_slot: &'a [u32],
}

impl<'a> MaterialSlots<'a> {
    /// Checks the slots against a mesh of `triangles` triangles.
    ///
    /// # Errors
    /// [`PeltError::InvalidParameter`] naming `materials.slots`, the bad slot's field or
    /// `materials.triangle_slot`.
    pub fn validate(&self, triangles: usize) -> Result<()> {
        if self.slots.len() > MAX_SLOTS {
            return Err(PeltError::parameter(
                "materials.slots",
                format!("must hold at most {MAX_SLOTS} slots, got {}", self.slots.len()),
            ));
        }
        for (s, material) in self.slots.iter().enumerate() {
            if let Some(material) = material {
                material.validate(&format!("materials.slots[{s}]"))?;
            }
        }
        if self.triangle_slot.len() != triangles {
            return Err(PeltError::parameter(
                "materials.triangle_slot",
                format!(
                    "must hold one slot per triangle ({triangles}), got {}",
                    self.triangle_slot.len()
                ),
            ));
        }
        if let Some(t) = self
            .triangle_slot
            .iter()
            .position(|&s| s as usize >= self.slots.len())
        {
            return Err(PeltError::parameter(
                format!("materials.triangle_slot[{t}]"),
                format!(
                    "must be a slot below {}, got {}",
                    self.slots.len(),
                    self.triangle_slot[t]
                ),
            ));
        }
        Ok(())
    }

    /// The own material triangle `t` keeps when bald, if its slot has one, with the slot.
    pub fn own(&self, t: usize) -> Option<(usize, &'a OwnMaterial)> {
        let slot = *self.triangle_slot.get(t)? as usize;
        self.slots.get(slot)?.as_ref().map(|m| (slot, m))
    }
}

impl OwnMaterial {
    fn validate(&self, name: &str) -> Result<()> {
        validate_name(&format!("{name}.name"), &self.name)?;
        let unit = |v: f32| (0.0..=1.0).contains(&v);
        if !self.base_color.iter().all(|&c| unit(c)) {
            return Err(PeltError::parameter(
                format!("{name}.base_color"),
                format!("must be 4 values in [0, 1], got {:?}", self.base_color),
            ));
        }
        for (field, value) in [("metallic", self.metallic), ("roughness", self.roughness)] {
            if !unit(value) {
                return Err(PeltError::parameter(
                    format!("{name}.{field}"),
                    format!("must be in [0, 1], got {}", Num(f64::from(value))),
                ));
            }
        }
        Ok(())
    }
}

/// The split skin's triangles (`indices`, three per mesh triangle, in mesh order) by what draws
/// them: Pelt's skin first, then one group per own material some bald triangle keeps (a
/// triangle is bald when `lengths` is 0 at its three corners), in slot order. When no triangle
/// would be left to Pelt's skin, every triangle stays on it (a glTF primitive needs one, and the
/// fur extension stands on it).
pub fn skin_groups<'a>(
    indices: &[u32],
    lengths: &[f32],
    slots: Option<&MaterialSlots<'a>>,
) -> (Vec<u32>, Vec<(&'a OwnMaterial, Vec<u32>)>) {
    let Some(slots) = slots else {
        return (indices.to_vec(), Vec::new());
    };
    let mut pelt = Vec::with_capacity(indices.len());
    let mut own: Vec<Vec<u32>> = vec![Vec::new(); slots.slots.len()];
    for (t, corners) in indices.chunks_exact(3).enumerate() {
        let bald = corners.iter().all(|&v| lengths[v as usize] <= 0.0);
        match slots.own(t) {
            Some((slot, _)) if bald => own[slot].extend_from_slice(corners),
            _ => pelt.extend_from_slice(corners),
        }
    }
    if pelt.is_empty() {
        return (indices.to_vec(), Vec::new());
    }
    let groups = own
        .into_iter()
        .enumerate()
        .filter(|(_, group)| !group.is_empty())
        .filter_map(|(slot, group)| Some((slots.slots[slot].as_ref()?, group)))
        .collect();
    (pelt, groups)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn eyes() -> OwnMaterial {
        OwnMaterial {
            name: "Eyes".into(),
            base_color: [0.0, 0.0, 0.0, 1.0],
            metallic: 0.0,
            roughness: 0.5,
        }
    }

    #[test]
    fn bald_faces_with_a_material_leave_the_skin_and_the_rest_stay() {
        // Four triangles over six vertices; vertices 3..6 bald.
        let indices = [0, 1, 2, 3, 4, 5, 2, 3, 4, 3, 4, 5];
        let lengths = [1.0, 1.0, 1.0, 0.0, 0.0, 0.0];
        let slots = [None, Some(eyes())];
        // Triangle 0 furred in slot 1, 1 bald in slot 1, 2 partly furred in slot 1, 3 bald in
        // the empty slot 0.
        let triangle_slot = [1, 1, 1, 0];
        let materials = MaterialSlots {
            slots: &slots,
            triangle_slot: &triangle_slot,
        };
        materials.validate(4).unwrap();
        let (pelt, own) = skin_groups(&indices, &lengths, Some(&materials));
        assert_eq!(pelt, [0, 1, 2, 2, 3, 4, 3, 4, 5]);
        assert_eq!(own, vec![(&eyes(), vec![3, 4, 5])]);
        // Without slots, or when nothing would be left to Pelt's skin, it keeps every face.
        assert_eq!(skin_groups(&indices, &lengths, None).0, indices);
        let all_bald = [0.0; 6];
        let every = [1, 1, 1, 1];
        let materials = MaterialSlots {
            slots: &slots,
            triangle_slot: &every,
        };
        assert_eq!(
            skin_groups(&indices, &all_bald, Some(&materials)),
            (indices.to_vec(), vec![])
        );
    }

    #[test]
    fn bad_slots_are_named() {
        let slots = [None, Some(eyes())];
        let check = |slots: &[Option<OwnMaterial>], triangle_slot: &[u32]| {
            MaterialSlots { slots, triangle_slot }
                .validate(2)
                .unwrap_err()
                .to_string()
        };
        assert!(check(&slots, &[0]).contains("materials.triangle_slot"));
        assert!(check(&slots, &[0, 2]).contains("materials.triangle_slot[1]"));
        let mut bad = eyes();
        bad.base_color[1] = f32::NAN;
        assert!(check(&[Some(bad)], &[0, 0]).contains("materials.slots[0].base_color"));
        let mut bad = eyes();
        bad.roughness = 1.5;
        assert!(check(&[Some(bad)], &[0, 0]).contains("materials.slots[0].roughness"));
        let mut bad = eyes();
        bad.name = String::new();
        assert!(check(&[Some(bad)], &[0, 0]).contains("materials.slots[0].name"));
    }
}
