//! An OBJ's materials: its MTL files (`mtllib`) read with `tobj`, each
//! material made a scene material. Problems with them are warnings, as in
//! other renderers: a missing MTL or image leaves the faces grey or
//! untextured, a bad value is replaced by its default.

use crate::images::ImageCache;
use crate::model::{ImageTexture, Material, TextureRef, TextureScale, Wrap};
use crate::source::Source;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The MTL files an OBJ asked for, in its order: each with its path and
/// the materials it gave, or why it could not be read.
pub struct Libraries<'a> {
    folder: PathBuf,
    source: &'a dyn Source,
    read: Vec<(PathBuf, Result<Vec<tobj::Material>, String>)>,
}

/// What the MTL files an OBJ read gave (the files themselves are recorded
/// by the source they were read from).
#[derive(Debug, Default)]
pub struct ObjMaterials {
    pub materials: Vec<Material>,
    pub warnings: Vec<String>,
}

impl<'a> Libraries<'a> {
    /// MTL files named relative to `folder` (the OBJ file's), read from `source`.
    pub fn new(folder: &Path, source: &'a dyn Source) -> Self {
        Libraries {
            folder: folder.to_path_buf(),
            source,
            read: Vec::new(),
        }
    }

    /// The materials of every file read (in the order read), made scene
    /// materials, with their images read through `images`.
    pub fn finish(self, images: &mut ImageCache) -> ObjMaterials {
        let mut out = ObjMaterials::default();
        for (path, found) in self.read {
            let name = file_name(&path);
            let found = match found {
                Ok(found) => found,
                Err(e) => {
                    out.warnings.push(format!(
                        "material library `{name}` cannot be read ({e}); its faces are drawn in the default grey"
                    ));
                    continue;
                }
            };
            let folder = path.parent().unwrap_or(Path::new(""));
            let first_warning = out.warnings.len();
            for m in &found {
                let material = scene_material(m, folder, (self.source, images), &mut out);
                out.materials.push(material);
            }
            for warning in &mut out.warnings[first_warning..] {
                *warning = format!("`{name}`: {warning}");
            }
        }
        out
    }
}

impl crate::obj_text::MaterialLibraries for Libraries<'_> {
    /// Reads the MTL file `name` and keeps what it gave.
    fn load(&mut self, name: &Path) -> Vec<String> {
        let path = self.folder.join(name);
        let result = self
            .source
            .open(&path, crate::read::MAX_OBJ_BYTES)
            .and_then(|mut file| {
                let mut bytes = Vec::new();
                file.read_to_end(&mut bytes).map(|_| bytes)
            })
            .map_err(|e| e.to_string())
            .and_then(|bytes| parse_mtl(&bytes));
        let names = result.iter().flatten().map(|m| m.name.clone()).collect();
        self.read.push((path, result));
        names
    }
}

/// The materials of one MTL file's bytes, as an OBJ's `mtllib` gives them:
/// its `map_Kd` images read from `source` relative to `folder`, its
/// problems as warnings. (The fuzz target's way in.)
pub fn read_mtl_bytes(
    bytes: &[u8],
    folder: &Path,
    source: &dyn Source,
    images: &mut ImageCache,
) -> Result<ObjMaterials, String> {
    let found = parse_mtl(bytes)?;
    let mut out = ObjMaterials::default();
    for m in &found {
        let material = scene_material(m, folder, (source, images), &mut out);
        out.materials.push(material);
    }
    Ok(out)
}

/// The materials of an MTL file's bytes, read by tobj once the lines it
/// would panic on are refused: a colour (`Ka`, `Kd`, `Ks`, `Ke`) of fewer
/// than 3 numbers (tobj 4.0.5 unwraps them; found by the `mtl` fuzz target).
fn parse_mtl(bytes: &[u8]) -> Result<Vec<tobj::Material>, String> {
    for (n, line) in String::from_utf8_lossy(bytes).lines().enumerate() {
        let mut words = line.split_whitespace();
        if let Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")) = words.next() {
            let found = words.take(3).count();
            if found < 3 {
                return Err(format!(
                    "not a valid MTL file: line {}: `{key}` needs 3 numbers, found {found}",
                    n + 1
                ));
            }
        }
    }
    tobj::load_mtl_buf(&mut std::io::Cursor::new(bytes))
        .map(|(materials, _)| materials)
        .map_err(|e| format!("not a valid MTL file: {e}"))
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .unwrap_or(path.as_os_str())
        .to_string_lossy()
        .into_owned()
}

/// An MTL material as a scene material: keys left out are 0, as in a
/// scene file; `map_Kd` is read relative to `folder` (the MTL file's).
fn scene_material(
    m: &tobj::Material,
    folder: &Path,
    images: (&dyn Source, &mut ImageCache),
    out: &mut ObjMaterials,
) -> Material {
    let mut material = Material {
        ambient: m.ambient.unwrap_or_default(),
        diffuse: m.diffuse.unwrap_or_default(),
        specular: m.specular.unwrap_or_default(),
        shininess: m.shininess.unwrap_or_default(),
        transmittance: transmittance(m, out),
        // `Ke`: the emitted radiance, as exporters write area lights.
        emission: m.emissive.unwrap_or_default(),
        ..Material::default()
    };
    if let Some(ior) = m.optical_density.filter(|&n| n > 0.0) {
        material.ior = ior;
    }
    if let Some(name) = &m.diffuse_texture {
        material.texture = diffuse_map(&m.name, name, folder, images, out);
    }
    keep_valid(&m.name, &mut material, out);
    material
}

/// `1 - d` (d is opacity), else `Tr` (transparency), else 0.
fn transmittance(m: &tobj::Material, out: &mut ObjMaterials) -> f32 {
    if let Some(d) = m.dissolve {
        return 1.0 - d;
    }
    let Some(tr) = m.unknown_param.get("Tr") else {
        return 0.0;
    };
    tr.parse().unwrap_or_else(|_| {
        out.warnings.push(format!(
            "material `{}`: expected a number for `Tr`, found `{tr}`; 0 used",
            m.name
        ));
        0.0
    })
}

/// The image texture of `map_Kd name`; options before the file name
/// (`-s 2 2 2 wood.png`) are not read, with a warning.
fn diffuse_map(
    material: &str,
    name: &str,
    folder: &Path,
    (source, images): (&dyn Source, &mut ImageCache),
    out: &mut ObjMaterials,
) -> Option<TextureRef> {
    let mut file = name;
    if name.starts_with('-') {
        file = name.split_whitespace().last().unwrap_or(name);
        out.warnings.push(format!(
            "material `{material}`: the options of `map_Kd {name}` are not read; the image `{file}` is used as it is"
        ));
    }
    let path = folder.join(file);
    match images.get(source, &path) {
        Ok(data) => Some(TextureRef::Image(ImageTexture {
            image: file.to_string(),
            scale: TextureScale::default(),
            wrap: Wrap::Repeat,
            wrap_v: None,
            rotate: 0.0,
            offset: [0.0; 2],
            data: Some(data),
        })),
        Err(e) => {
            out.warnings.push(format!(
                "material `{material}`: cannot load `map_Kd` image `{file}` ({e}); drawn without it"
            ));
            None
        }
    }
}

/// Every value validation refuses is put back to its default, with a
/// warning in the MTL's own key names.
fn keep_valid(name: &str, material: &mut Material, out: &mut ObjMaterials) {
    for d in crate::validate::material(material) {
        let key = d.path.to_string();
        let (mtl_key, reset): (&str, fn(&mut Material)) = match key.as_str() {
            "ambient" => ("Ka", |m| m.ambient = [0.0; 3]),
            "diffuse" => ("Kd", |m| m.diffuse = [0.0; 3]),
            "specular" => ("Ks", |m| m.specular = [0.0; 3]),
            "shininess" => ("Ns", |m| m.shininess = 0.0),
            "transmittance" => ("d` or `Tr", |m| m.transmittance = 0.0),
            "ior" => ("Ni", |m| m.ior = crate::model::DEFAULT_IOR),
            "emission" => ("Ke", |m| m.emission = [0.0; 3]),
            _ => ("", |_| {}),
        };
        reset(material);
        let message = match mtl_key {
            // The message is about the transmittance it makes.
            "d` or `Tr" => format!("as transmittance (1 - d, or Tr) {}", d.message),
            _ => d.message,
        };
        out.warnings.push(format!(
            "material `{name}`, `{mtl_key}`: {message}; its default used"
        ));
    }
    // Only the keys above can fail for a material made here.
    debug_assert!(crate::validate::material(material).is_empty());
}

#[cfg(test)]
mod tests {
    use crate::images::ImageCache;
    use crate::obj::read_obj_from;
    use crate::source::{Folder, Source};

    #[test]
    fn a_colour_of_fewer_than_three_numbers_is_a_warning_not_a_panic() {
        // tobj 4.0.5 panicked on each of these (the `mtl` fuzz target).
        for colour in ["Ka 0.1", "Kd", "Ks 1 2", "  Ke 1\r"] {
            let dir = tempfile::tempdir().unwrap();
            let obj = "mtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
            std::fs::write(dir.path().join("m.obj"), obj).unwrap();
            let mtl = format!("newmtl m\nNs 20\n{colour}\n");
            std::fs::write(dir.path().join("b.mtl"), mtl).unwrap();
            let obj = dir.path().join("m.obj");
            let data = read_obj_from(&Folder::new(), &obj, &mut ImageCache::default()).unwrap();
            let w = &data.material_warnings;
            assert_eq!(w.len(), 1, "{w:?}");
            assert!(w[0].contains("line 3: `K"), "{}", w[0]);
            assert!(w[0].contains("needs 3 numbers"), "{}", w[0]);
        }
    }

    #[test]
    fn faces_keep_their_material_across_libraries_one_of_them_missing() {
        let dir = tempfile::tempdir().unwrap();
        let obj = "mtllib none.mtl\nmtllib b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n\
                   f 1 2 3\nusemtl second\nf 1 2 3\nusemtl first\nf 1 3 2\nusemtl nowhere\nf 2 1 3\n";
        std::fs::write(dir.path().join("m.obj"), obj).unwrap();
        let mtl = "newmtl first\nKd 1 0 0\nnewmtl second\nKd 0 1 0\nmap_Kd -s 2 2 1 missing.png\n";
        std::fs::write(dir.path().join("b.mtl"), mtl).unwrap();
        let folder = Folder::new();
        let obj = dir.path().join("m.obj");
        let data = read_obj_from(&folder, &obj, &mut ImageCache::default()).unwrap();
        assert_eq!(data.materials.len(), 2);
        assert_eq!(data.materials[0].diffuse, [1.0, 0.0, 0.0]);
        assert_eq!(data.materials[1].diffuse, [0.0, 1.0, 0.0]);
        // No usemtl yet, `second`, `first`, an undefined name.
        assert_eq!(data.triangle_materials, [None, Some(1), Some(0), None]);
        // Read: the OBJ and the one library there is (not `none.mtl`, not
        // the missing image).
        assert_eq!(folder.files_read(), [obj, dir.path().join("b.mtl")]);
        let w = &data.material_warnings;
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(
            w[0].starts_with("material library `none.mtl` cannot be read"),
            "{}",
            w[0]
        );
        assert!(
            w[1].contains("the options of `map_Kd -s 2 2 1 missing.png` are not read"),
            "{}",
            w[1]
        );
        assert!(
            w[2].starts_with(
                "`b.mtl`: material `second`: cannot load `map_Kd` image `missing.png`"
            ),
            "{}",
            w[2]
        );
    }
}
