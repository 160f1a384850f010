//! DNA as a helically reinforced thin tube (physics.md §1.5 "DNA scene").
