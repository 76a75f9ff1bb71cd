use crate::test_support::{parameter_name, random_bytes, with_threads};
use crate::texture::atlas::{AtlasLayout, pack_atlas, pack_validated};

#[test]
fn layout_is_the_smallest_square_grid_that_holds_the_layers() {
    let expected = [
        (1, 1, 1),
        (2, 2, 1),
        (4, 2, 2),
        (5, 3, 2),
        (10, 4, 3),
        (16, 4, 4),
        (17, 5, 4),
    ];
    for (layers, columns, rows) in expected {
        let layout = AtlasLayout::new(layers, 128).unwrap();
        assert_eq!((layout.columns, layout.rows), (columns, rows), "{layers} layers");
        assert_eq!((layout.width, layout.height), (columns * 128, rows * 128));
    }
    for layers in 1..=300usize {
        let layout = AtlasLayout::new(layers, 3).unwrap();
        // columns = ⌈√L⌉: the smallest c with c² ≥ L; rows = ⌈L / c⌉.
        let c = layout.columns;
        assert!(c * c >= layers && (c - 1) * (c - 1) < layers, "{layers}");
        assert!(
            layout.rows * c >= layers && (layout.rows - 1) * c < layers,
            "{layers}"
        );
    }
}

#[test]
fn tile_origins_run_left_to_right_then_top_to_bottom() {
    let layout = AtlasLayout::new(5, 10).unwrap();
    let origins: Vec<(usize, usize)> = (0..5).map(|l| layout.tile_origin(l).unwrap()).collect();
    assert_eq!(origins, [(0, 0), (10, 0), (20, 0), (0, 10), (10, 10)]);
    assert_eq!(parameter_name(layout.tile_origin(5)), "layer");
}

#[test]
fn every_layer_lands_where_the_layout_says_and_the_rest_is_zero() {
    let (layers, tile, channels) = (7, 5, 2);
    let data = random_bytes(1, layers * tile * tile * channels);
    let layout = AtlasLayout::new(layers, tile).unwrap();
    let atlas = pack_atlas(&layout, channels, &data).unwrap();
    assert_eq!((atlas.width(), atlas.height(), atlas.channels()), (15, 15, 2));
    let mut from_a_layer = vec![false; atlas.width() * atlas.height()];
    for layer in 0..layers {
        let (ox, oy) = layout.tile_origin(layer).unwrap();
        for y in 0..tile {
            for x in 0..tile {
                let pixel = (oy + y) * atlas.width() + ox + x;
                let src = ((layer * tile + y) * tile + x) * channels;
                assert_eq!(
                    &atlas.data()[pixel * channels..(pixel + 1) * channels],
                    &data[src..src + channels]
                );
                assert!(!from_a_layer[pixel], "pixel {pixel} written twice");
                from_a_layer[pixel] = true;
            }
        }
    }
    for (pixel, used) in from_a_layer.iter().enumerate() {
        if !used {
            assert_eq!(&atlas.data()[pixel * channels..(pixel + 1) * channels], &[0, 0]);
        }
    }
    // Seven tiles are used out of nine cells.
    assert_eq!(from_a_layer.iter().filter(|&&u| u).count(), layers * tile * tile);
}

#[test]
fn packing_does_not_depend_on_the_thread_count() {
    let layout = AtlasLayout::new(10, 17).unwrap();
    let data = random_bytes(2, 10 * 17 * 17 * 4);
    let one = with_threads(1, || pack_validated(&layout, 4, &data));
    let two = with_threads(2, || pack_validated(&layout, 4, &data));
    assert_eq!(one, two);
}

#[test]
fn layout_serializes_with_every_field_and_reads_back() {
    let layout = AtlasLayout::new(16, 128).unwrap();
    let json = serde_json::to_value(layout).unwrap();
    assert_eq!(
        json,
        serde_json::json!({"layers": 16, "tile": 128, "columns": 4, "rows": 4,
                           "width": 512, "height": 512})
    );
    let back: AtlasLayout = serde_json::from_value(json).unwrap();
    assert_eq!(back, layout);
}

#[test]
fn bad_layouts_and_data_are_rejected() {
    assert_eq!(parameter_name(AtlasLayout::new(0, 4)), "layers");
    assert_eq!(parameter_name(AtlasLayout::new(4, 0)), "tile");
    assert_eq!(parameter_name(AtlasLayout::new(4, usize::MAX / 2)), "tile");
    let layout = AtlasLayout::new(4, 2).unwrap();
    let data = vec![0u8; 4 * 2 * 2 * 3];
    let edited = AtlasLayout { columns: 4, ..layout };
    assert_eq!(parameter_name(pack_atlas(&edited, 3, &data)), "layout");
    assert_eq!(parameter_name(pack_atlas(&layout, 0, &data)), "channels");
    assert_eq!(parameter_name(pack_atlas(&layout, 3, &data[1..])), "data");
}
