use crate::test_support::parameter_name;
use crate::texture::image::{Image, ImageRef, MAX_DIMENSION, layer_views};

#[test]
fn image_ref_accepts_matching_length_and_exposes_rows() {
    let data: Vec<u8> = (0..2 * 3 * 4).map(|v| v as u8).collect();
    let image = ImageRef::new(2, 3, 4, &data).unwrap();
    assert_eq!((image.width(), image.height(), image.channels()), (2, 3, 4));
    // Row y starts at sample y · width · channels.
    assert_eq!(image.row(0).unwrap(), &data[0..8]);
    assert_eq!(image.row(2).unwrap(), &data[16..24]);
    assert!(image.row(3).is_none());
}

#[test]
fn image_ref_rejects_bad_sizes_naming_the_parameter() {
    let data = [0u8; 12];
    assert_eq!(parameter_name(ImageRef::new(0, 3, 4, &data)), "width");
    assert_eq!(parameter_name(ImageRef::new(1, 0, 4, &data)), "height");
    assert_eq!(parameter_name(ImageRef::new(1, 3, 0, &data)), "channels");
    assert_eq!(parameter_name(ImageRef::new(1, 3, 5, &data)), "channels");
    assert_eq!(parameter_name(ImageRef::new(2, 3, 4, &data)), "data");
    assert_eq!(
        parameter_name(ImageRef::new(MAX_DIMENSION + 1, 1, 1, &data)),
        "width"
    );
    assert_eq!(parameter_name(Image::new(2, 2, 2, vec![0u8; 7])), "data");
}

#[test]
fn owned_image_views_its_data() {
    let image = Image::new(3, 1, 2, vec![1u16, 2, 3, 4, 5, 6]).unwrap();
    assert_eq!(image.view().data(), &[1, 2, 3, 4, 5, 6]);
    assert_eq!(image.view().row(0).unwrap(), image.data());
    assert_eq!(image.into_data(), vec![1, 2, 3, 4, 5, 6]);
}

#[test]
fn layer_views_split_layer_major_data() {
    let (w, h, c, l) = (3, 2, 2, 4);
    let data: Vec<u32> = (0..(w * h * c * l) as u32).collect();
    let views = layer_views(w, h, c, l, &data).unwrap();
    assert_eq!(views.len(), l);
    for (layer, view) in views.iter().enumerate() {
        // Layer `layer` starts at sample layer · w · h · c.
        assert_eq!(view.data()[0] as usize, layer * w * h * c);
        assert_eq!(view.data().len(), w * h * c);
    }
    assert_eq!(parameter_name(layer_views(w, h, c, 0, &data)), "layers");
    assert_eq!(parameter_name(layer_views(w, h, c, 3, &data)), "data");
}
