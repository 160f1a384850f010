! Module procedures of the Fortran module `rodkit`, appended after `contains`
! by codegen/fortran.rs (the interfaces before them are generated from the
! header's definitions). Written by hand: they wrap C strings, which the
! generated interfaces return as type(c_ptr).

    ! Description of a status code as a Fortran string (a copy of
    ! rodkit_status_string(code)); e.g. "success" for RODKIT_STATUS_OK.
    function rodkit_status_message(code) result(message)
        integer(c_int32_t), intent(in) :: code
        character(len=:), allocatable :: message
        message = c_string_to_fortran(rodkit_status_string(code))
    end function rodkit_status_message

    ! The last-error message of the calling thread as a Fortran string (a
    ! copy: it stays valid whatever rodkit is called next); "" if the last
    ! rodkit call succeeded. Obtained with rodkit_last_error_copy: a size
    ! query, then a copy into a buffer of exactly the right size. Does not
    ! change the message.
    function rodkit_last_error() result(message)
        character(len=:), allocatable :: message
        character(len=1, kind=c_char) :: probe
        character(len=:, kind=c_char), allocatable :: buffer
        integer(c_int64_t) :: length, copied
        integer(c_int32_t) :: status
        integer :: n, i

        length = 0
        status = rodkit_last_error_copy(probe, 1_c_int64_t, length)
        if (status < 0 .or. length <= 0) then
            message = ""
            if (status < 0) message = "rodkit_last_error: could not read the message"
            return
        end if
        allocate(character(len=int(length) + 1, kind=c_char) :: buffer)
        status = rodkit_last_error_copy(buffer, length + 1, copied)
        if (status < 0) then
            message = "rodkit_last_error: could not read the message"
            return
        end if
        ! The text ends at the first NUL (the copy is always NUL-terminated).
        n = index(buffer, c_null_char) - 1
        if (n < 0) n = len(buffer)
        allocate(character(len=n) :: message)
        do i = 1, n
            message(i:i) = buffer(i:i)
        end do
    end function rodkit_last_error

    ! Copy of a NUL-terminated C string owned by rodkit ("" for NULL).
    function c_string_to_fortran(ptr) result(text)
        type(c_ptr), intent(in) :: ptr
        character(len=:), allocatable :: text
        character(kind=c_char), pointer :: chars(:)
        integer :: n, i

        if (.not. c_associated(ptr)) then
            text = ""
            return
        end if
        call c_f_pointer(ptr, chars, [huge(0)])
        n = 0
        do while (chars(n + 1) /= c_null_char)
            n = n + 1
        end do
        allocate(character(len=n) :: text)
        do i = 1, n
            text(i:i) = chars(i)
        end do
    end function c_string_to_fortran
