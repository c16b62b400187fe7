#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    luxbake_fuzz::accessors(data);
});
