//! Texture sets read back with independent readers: the `ktx2` crate (format, layers, levels,
//! byte sizes; pixels equal to the PNG layers decoded by the `png` crate), the `exr` crate, and
//! the manifest parsed back; determinism across runs and thread counts; errors.

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::Path;

use ::exr::prelude::traits::*;
use ::exr::prelude::{FlatSamples, read};
use half::f16;

use super::fixture::{Fixture, ORDER};
use super::glb_reader::decode_png;
use super::{parameter_name, temp_dir, with_threads};
use crate::export::{MANIFEST_NAME, Manifest, TextureFormats, write_texture_set};

fn read_file(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap()
}

/// Level bytes of a KTX2 file (base first) after checking its header against the expectations.
fn ktx2_levels(
    bytes: &[u8],
    format: u32,
    size: [u32; 2],
    layers: u32,
    levels: usize,
    texel: usize,
) -> Vec<Vec<u8>> {
    let reader = ::ktx2::Reader::new(bytes).unwrap();
    let header = reader.header();
    assert_eq!(header.format.map(|f| f.value()), Some(format));
    assert_eq!([header.pixel_width, header.pixel_height], size);
    assert_eq!(header.layer_count, layers);
    assert_eq!(header.level_count as usize, levels);
    let data: Vec<Vec<u8>> = reader.levels().map(|l| l.data.to_vec()).collect();
    for (i, level) in data.iter().enumerate() {
        let (w, h) = ((size[0] as usize >> i).max(1), (size[1] as usize >> i).max(1));
        assert_eq!(level.len(), w * h * layers.max(1) as usize * texel, "level {i}");
    }
    data
}

/// The one-layer channel data of an EXR file, by channel name.
fn exr_channels(bytes: &[u8]) -> (usize, usize, BTreeMap<String, FlatSamples>) {
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .non_parallel()
        .from_buffered(Cursor::new(bytes))
        .unwrap();
    let layer = &image.layer_data[0];
    let channels = layer
        .channel_data
        .list
        .iter()
        .map(|c| (c.name.to_string(), c.sample_data.clone()))
        .collect();
    (layer.size.0, layer.size.1, channels)
}

#[test]
fn every_format_reads_back_with_independent_readers() {
    let fx = Fixture::new();
    let dir = temp_dir("texture-set");
    let manifest = write_texture_set(&[fx.input("Fox Tail")], &dir, TextureFormats::default()).unwrap();
    let (v, stem) = (&fx.volume, "Fox_Tail");
    let (l, r) = (v.layers, v.resolution);

    // The manifest on disk is the one returned, and lists exactly the files written.
    assert_eq!(Manifest::load(&dir).unwrap(), manifest);
    let object = &manifest.objects[0];
    assert_eq!(object.name, "Fox Tail");
    let mut listed: Vec<&str> = object.files.iter().map(|f| f.path.as_str()).collect();
    listed.push(MANIFEST_NAME);
    listed.sort_unstable();
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    on_disk.sort_unstable();
    assert_eq!(listed, on_disk);
    for file in &object.files {
        assert_eq!(
            file.bytes,
            std::fs::metadata(dir.join(&file.path)).unwrap().len(),
            "{}",
            file.path
        );
    }

    // Shell array: RGBA8 sRGB (VkFormat 43), L layers, the bake's levels; level 0 layer by layer
    // equals the PNG layers, the other levels the bake's mips.
    let levels = ktx2_levels(
        &read_file(&dir, &format!("{stem}_shells.ktx2")),
        43,
        [r as u32; 2],
        l as u32,
        1 + v.mips.len(),
        4,
    );
    for layer in 0..l {
        let (png, w, h) = decode_png(&read_file(&dir, &format!("{stem}_layer_{layer:03}.png")));
        assert_eq!((w as usize, h as usize), (r, r));
        assert_eq!(
            png,
            levels[0][layer * r * r * 4..(layer + 1) * r * r * 4],
            "layer {layer}"
        );
    }
    for (k, mip) in v.mips.iter().enumerate() {
        assert_eq!(&levels[k + 1], mip);
    }
    let entry = object.files.iter().find(|f| f.kind == "shell_array").unwrap();
    assert_eq!((entry.layers, entry.levels), (Some(l), Some(1 + v.mips.len())));

    // Tangents: RGBA8 UNORM (37), full chain; the base equals the volume's tangents and the
    // tangent atlas PNG.
    let full = (usize::BITS - r.leading_zeros()) as usize;
    let tangents = ktx2_levels(
        &read_file(&dir, &format!("{stem}_tangents.ktx2")),
        37,
        [r as u32; 2],
        l as u32,
        full,
        4,
    );
    assert_eq!(tangents[0], v.tangents);
    let (atlas, aw, _) = decode_png(&read_file(&dir, &format!("{stem}_tangents_atlas.png")));
    let columns = aw as usize / r;
    for layer in 0..l {
        for y in 0..r {
            let row = (layer / columns) * r + y;
            let at = (row * aw as usize + (layer % columns) * r) * 4;
            let want = &v.tangents[((layer * r + y) * r) * 4..][..r * 4];
            assert_eq!(&atlas[at..at + r * 4], want);
        }
    }

    // Fin: a plain 2D texture (layer count 0) with a full chain, base = the fin PNG.
    let [fw, fh] = v.fin_size;
    let fin_levels = (usize::BITS - fw.max(fh).leading_zeros()) as usize;
    let fin = ktx2_levels(
        &read_file(&dir, &format!("{stem}_fin.ktx2")),
        43,
        [fw as u32, fh as u32],
        0,
        fin_levels,
        4,
    );
    assert_eq!(fin[0], decode_png(&read_file(&dir, &format!("{stem}_fin.png"))).0);
    assert_eq!(fin[0], v.fin);

    // Transfer: RGBA16F (97), T · L layers, texture-major: the base level is the packed texels.
    let textures = fx.f16.textures;
    assert_eq!(textures, (ORDER * ORDER).div_ceil(4));
    let transfer = ktx2_levels(
        &read_file(&dir, &format!("{stem}_transfer.ktx2")),
        97,
        [r as u32; 2],
        (textures * l) as u32,
        full,
        8,
    );
    let halves: Vec<f16> = transfer[0]
        .chunks_exact(2)
        .map(|b| f16::from_le_bytes([b[0], b[1]]))
        .collect();
    assert_eq!(halves, fx.f16.texels);

    // EXR: the density atlas holds the coverage; the transfer atlas the float16 coefficients.
    let (w, h, channels) = exr_channels(&read_file(&dir, &format!("{stem}_density.exr")));
    assert_eq!((w, h), (columns * r, l.div_ceil(columns) * r));
    let FlatSamples::F32(density) = &channels["Y"] else {
        panic!("density is not FLOAT")
    };
    for layer in 0..l {
        let (cx, cy) = ((layer % columns) * r, (layer / columns) * r);
        for y in 0..r {
            for x in 0..r {
                assert_eq!(
                    density[(cy + y) * w + cx + x],
                    v.coverage[(layer * r + y) * r + x]
                );
            }
        }
    }
    let (_, _, channels) = exr_channels(&read_file(&dir, &format!("{stem}_transfer_0.exr")));
    let FlatSamples::F16(red) = &channels["R"] else {
        panic!("transfer is not HALF")
    };
    let layer = l - 1;
    let (cx, cy) = ((layer % columns) * r, (layer / columns) * r);
    for y in 0..r {
        for x in 0..r {
            let want = fx.f16.texels[((layer * r + y) * r + x) * 4];
            assert_eq!(red[(cy + y) * w + cx + x].to_bits(), want.to_bits());
        }
    }

    // 8-bit transfer PNG atlas: the packed bytes.
    let (png, _, _) = decode_png(&read_file(&dir, &format!("{stem}_transfer_0.png")));
    let at = ((cy * w + cx) * 4, ((layer * r) * r) * 4);
    assert_eq!(png[at.0..at.0 + 4 * r], fx.u8.texels[at.1..at.1 + 4 * r]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn formats_choose_the_files_and_output_is_reproducible() {
    let fx = Fixture::new();
    let objects = [fx.input("a"), fx.input("b")];
    let only_ktx2 = TextureFormats::parse("ktx2").unwrap();
    let dir = temp_dir("texture-set-ktx2");
    let manifest = write_texture_set(&objects, &dir, only_ktx2).unwrap();
    assert_eq!(manifest.objects.len(), 2);
    for object in &manifest.objects {
        assert!(object.files.iter().all(|f| f.format == "ktx2"));
        assert_eq!(object.files.len(), 4, "shells, tangents, fin, transfer");
    }
    std::fs::remove_dir_all(&dir).unwrap();

    let runs: Vec<BTreeMap<String, Vec<u8>>> = [1, 2, 2]
        .into_iter()
        .enumerate()
        .map(|(k, threads)| {
            let dir = temp_dir(&format!("texture-set-run{k}"));
            with_threads(threads, || {
                write_texture_set(&objects, &dir, TextureFormats::default()).unwrap()
            });
            let files = std::fs::read_dir(&dir)
                .unwrap()
                .map(|e| {
                    let e = e.unwrap();
                    (
                        e.file_name().to_string_lossy().into_owned(),
                        std::fs::read(e.path()).unwrap(),
                    )
                })
                .collect();
            std::fs::remove_dir_all(&dir).unwrap();
            files
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
    assert_eq!(runs[1], runs[2]);
}

#[test]
fn bad_requests_are_named() {
    let fx = Fixture::new();
    let dir = temp_dir("texture-set-bad");
    assert_eq!(parameter_name(TextureFormats::parse("png,tiff")), "formats");
    let none = TextureFormats {
        png: false,
        ktx2: false,
        exr: false,
    };
    assert_eq!(
        parameter_name(write_texture_set(&[fx.input("a")], &dir, none)),
        "formats"
    );
    // "a b" and "a_b" would write the same files.
    let clash = [fx.input("a b"), fx.input("a_b")];
    assert_eq!(
        parameter_name(write_texture_set(&clash, &dir, TextureFormats::default())),
        "objects"
    );
    // A folder that is a file.
    let file = dir.join("file");
    std::fs::write(&file, b"x").unwrap();
    assert!(matches!(
        write_texture_set(&[fx.input("a")], &file, TextureFormats::default()),
        Err(crate::PeltError::Io { .. })
    ));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_asset_folder_lists_its_glbs_beside_the_textures() {
    let fx = Fixture::new();
    let dir = temp_dir("asset");
    let options = crate::export::AssetOptions {
        formats: TextureFormats::parse("png").unwrap(),
        ..crate::export::AssetOptions::default()
    };
    let manifest = crate::export::write_asset(&[fx.input("a"), fx.input("b")], &dir, &options).unwrap();
    assert_eq!(Manifest::load(&dir).unwrap(), manifest);
    let glbs: Vec<(&str, Option<&str>)> = manifest
        .files
        .iter()
        .map(|f| (f.path.as_str(), f.mode.as_deref()))
        .collect();
    assert_eq!(
        glbs,
        [
            ("pelt_engine.glb", Some("engine")),
            ("pelt_geometry.glb", Some("geometry"))
        ]
    );
    for file in &manifest.files {
        let bytes = std::fs::read(dir.join(&file.path)).unwrap();
        assert_eq!(file.bytes, bytes.len() as u64);
        let glb = super::glb_reader::Glb::parse(&bytes);
        assert_eq!(glb.json["nodes"].as_array().unwrap().len(), 2);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
