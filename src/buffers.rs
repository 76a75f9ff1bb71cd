//! Large zeroed output buffers.
//!
//! A 1024² × 64 hair-volume bake writes over a gigabyte of fresh memory. The system allocator
//! maps a buffer that large lazily, so every 4 KiB page faults once when it is first written:
//! some 270,000 faults, about a tenth of the bake's time. On Linux the kernel can back such a
//! buffer with 2 MiB transparent huge pages when asked (`madvise(MADV_HUGEPAGE)`), which makes
//! 512 times fewer faults. It is advice only: where the kernel declines, or on other systems,
//! the buffer is the same, just slower to fill.

/// `len` zeroed elements (`zero` must be the type's all-zero value, so that the allocation is
/// the system's lazily mapped zeroed memory), backed by huge pages where the system allows.
pub fn zeroed<T: Copy>(len: usize, zero: T) -> Vec<T> {
    let buffer = vec![zero; len];
    advise_huge_pages(&buffer);
    buffer
}

/// Buffers smaller than this are left alone: too few pages to matter.
#[cfg(target_os = "linux")]
const MIN_BYTES: usize = 8 << 20;

#[cfg(target_os = "linux")]
fn advise_huge_pages<T>(buffer: &[T]) {
    const HUGE_PAGE: usize = 2 << 20;
    let bytes = std::mem::size_of_val(buffer);
    if bytes < MIN_BYTES {
        return;
    }
    let start = buffer.as_ptr() as usize;
    let first = start.next_multiple_of(HUGE_PAGE);
    let end = (start + bytes) / HUGE_PAGE * HUGE_PAGE;
    if end > first {
        // SAFETY: `first..end` lies inside `buffer`'s allocation; MADV_HUGEPAGE changes how the
        // kernel backs those pages, never their contents. A failure (no THP support) is ignored.
        unsafe {
            libc::madvise(first as *mut libc::c_void, end - first, libc::MADV_HUGEPAGE);
        }
    }
}

#[cfg(not(target_os = "linux"))]
fn advise_huge_pages<T>(_buffer: &[T]) {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeroed_buffers_are_zero_and_writable() {
        for len in [0, 1, 3 << 20, 5 << 20] {
            let mut bytes = zeroed(len, 0u8);
            assert_eq!(bytes.len(), len);
            assert!(bytes.iter().all(|&b| b == 0));
            if let Some(last) = bytes.last_mut() {
                *last = 7;
                assert_eq!(bytes[len - 1], 7);
            }
        }
        let floats = zeroed(3 << 20, 0.0f32);
        assert!(floats.iter().all(|&x| x.to_bits() == 0));
    }
}
