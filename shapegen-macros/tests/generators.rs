//! Generators that must compile and behave as written: each file in
//! `tests/pass/` is a small program whose `main` checks what its generator
//! makes, run here as a test.
//!
//! They are not trybuild cases (`tests/ui.rs`): with only compile-fail
//! cases, trybuild type-checks its copy of the dependencies instead of
//! building them, minutes less on a fresh checkout.

mod minimal {
    include!("pass/minimal.rs");

    #[test]
    fn runs() {
        main();
    }
}

mod custom_state_and_arrays {
    include!("pass/custom_state_and_arrays.rs");

    #[test]
    fn runs() {
        main();
    }
}

mod families_and_short_forms {
    include!("pass/families_and_short_forms.rs");

    #[test]
    fn runs() {
        main();
    }
}

mod tags {
    include!("pass/tags.rs");

    #[test]
    fn runs() {
        main();
    }
}

mod splits {
    include!("pass/splits.rs");

    #[test]
    fn runs() {
        main();
    }
}
